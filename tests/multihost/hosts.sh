# Three "hosts" for tests/multihost/run.sh: network namespaces on one bridge, each with its own
# address on 10.123.0.0/24 and its own hostname (given by netns_agent.sh). Sourced, not run.
# Needs root (CAP_NET_ADMIN, CAP_SYS_ADMIN), iproute2 and util-linux's unshare.
#   hosts_up       creates them; hosts_down removes every trace (called from an EXIT trap)
#   on_host H CMD  runs CMD on host H, as the launch agent does
#   host_pids H    the processes on host H (its network namespace)
#   cut_link H     takes host H's cable out (its port on the bridge goes down)

HOSTS=(farm1 farm2 farm3)
SUBNET=10.123.0.0/24
# Names unique to this run, so that two runs (or another helper's) never share a namespace.
RF_NETNS_PREFIX="rf$$-"
BRIDGE="rf$$br"
AGENT="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)/netns_agent.sh"
export RF_NETNS_PREFIX

host_ns() { echo "$RF_NETNS_PREFIX$1"; }
host_port() { echo "rf$$p${1#farm}"; }  # the bridge side of host H's cable

hosts_up() {
    ip link add "$BRIDGE" type bridge
    ip link set "$BRIDGE" up
    local i=0 h ns
    for h in "${HOSTS[@]}"; do
        i=$((i + 1))
        ns=$(host_ns "$h")
        ip netns add "$ns"
        # Names resolve inside the namespaces only: ip netns exec mounts /etc/netns/NS/hosts
        # over /etc/hosts, so the machine's own /etc/hosts is never edited.
        mkdir -p "/etc/netns/$ns"
        {
            echo "127.0.0.1 localhost"
            local j=0 g
            for g in "${HOSTS[@]}"; do j=$((j + 1)); echo "10.123.0.$j $g"; done
        } > "/etc/netns/$ns/hosts"
        ip link add "$(host_port "$h")" type veth peer name eth0 netns "$ns"
        ip link set "$(host_port "$h")" master "$BRIDGE" up
        ip netns exec "$ns" ip addr add "10.123.0.$i/24" dev eth0
        ip netns exec "$ns" ip link set eth0 up
        ip netns exec "$ns" ip link set lo up
    done
}

host_pids() { ip netns pids "$(host_ns "$1")" 2>/dev/null || true; }

on_host() { local h=$1; shift; "$AGENT" "$h" "$(printf '%q ' "$@")"; }

cut_link() { ip link set "$(host_port "$1")" down; }

# Plugs host H's cable back in and waits (up to 10 s) until farm1 reaches it over TCP again: the
# next mpirun's daemon there must connect back at once, and right after the link comes up the
# first connections can fail ("ORTE was unable to reliably start one or more daemons").
restore_link() {
    local h=$1 port=47999 i
    ip link set "$(host_port "$h")" up
    ip netns exec "$(host_ns "$h")" python3 -c '
import socket, sys
s = socket.socket()
s.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
s.bind(("0.0.0.0", int(sys.argv[1])))
s.listen(8)
s.settimeout(10)
try:
    s.accept()[0].close()
except socket.timeout:
    pass' "$port" &
    local listener=$!
    for i in $(seq 100); do
        ip netns exec "$(host_ns farm1)" python3 -c '
import socket, sys
socket.create_connection((sys.argv[1], int(sys.argv[2])), timeout=0.5).close()' "$h" "$port" 2> /dev/null && break
        sleep 0.1
    done
    wait "$listener" 2> /dev/null || true
}

hosts_down() {
    local h ns pids
    for h in "${HOSTS[@]}"; do
        ns=$(host_ns "$h")
        pids=$(host_pids "$h")
        # Only this run's processes live in this run's namespaces.
        [ -z "$pids" ] || kill -9 $pids 2>/dev/null || true
    done
    for h in "${HOSTS[@]}"; do
        ns=$(host_ns "$h")
        ip netns del "$ns" 2>/dev/null || true
        rm -rf "/etc/netns/$ns"
    done
    rmdir /etc/netns 2>/dev/null || true  # only if no other run still uses it
    ip link del "$BRIDGE" 2>/dev/null || true
}
