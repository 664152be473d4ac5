#!/usr/bin/env bash
# Open MPI launch agent (--mca plm_rsh_agent) standing in for ssh between network namespaces:
#   netns_agent.sh HOST COMMAND...
# runs COMMAND, as ssh would (one shell string), inside the namespace RF_NETNS_PREFIX+HOST with
# its own hostname HOST, so Open MPI's daemon there sees itself as that host.
set -euo pipefail
host=$1
shift
ns="${RF_NETNS_PREFIX:?RF_NETNS_PREFIX is not set}$host"
# ip netns exec also mounts /etc/netns/NS/hosts over /etc/hosts, so names resolve inside only.
exec ip netns exec "$ns" unshare --uts /bin/sh -c 'hostname "$1" && shift && eval "$*"' sh "$host" "$@"
