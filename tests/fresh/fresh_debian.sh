#!/usr/bin/env bash
# The first hour on a fresh Debian 12 machine, for real (issue 47 #1 and #3): a Debian 12
# (bookworm) made fresh with debootstrap --variant=minbase (nothing but apt and its essentials:
# no compiler, no CMake, no library), a clone of this repository copied in, then
#   1. `bash examples/quickstart.sh` timed as a whole (install, build, the demo film), each
#      phase's time from its first line of output;
#   2. `cpack -G DEB` in the quickstart's build folder;
#   3. a second fresh Debian 12 where `apt install ./rayfarm_*.deb` installs it, and `rayfarm
#      render` runs from PATH, alone and under `mpirun -np 2`, to the same frames.
# Root only (debootstrap, chroot, mounts); needs deb.debian.org. Opt-in, not in the default
# suite (about 8 minutes on 2 cores): bash tests/fresh/fresh_debian.sh [WORK_DIR]
# WORK_DIR (default /var/tmp/rayfarm-fresh) holds the chroots; they are removed at the end.
set -euo pipefail
src=$(cd "$(dirname "$0")/../.." && pwd)
work=${1:-/var/tmp/rayfarm-fresh}
mirror=${RAYFARM_DEBIAN_MIRROR:-http://deb.debian.org/debian}
[ "$(id -u)" -eq 0 ] || { echo "fresh_debian: needs root (debootstrap, chroot)" >&2; exit 2; }
command -v debootstrap >/dev/null || DEBIAN_FRONTEND=noninteractive apt-get install -y -qq debootstrap >/dev/null

root=$work/root
unmount() { for m in dev/pts dev proc sys; do umount -l "$root/$m" 2>/dev/null || true; done; }
cleanup() { unmount; rm -rf --one-file-system "$root"; }
trap cleanup EXIT
fresh() {  # a clean copy of the base system at $root, mounted
    unmount; rm -rf --one-file-system "$root"; mkdir -p "$root"
    tar -C "$root" -xf "$work/base.tar"
    mount --bind /dev "$root/dev"; mount --bind /dev/pts "$root/dev/pts"
    mount -t proc proc "$root/proc"; mount -t sysfs sys "$root/sys"
}
in_root() { chroot "$root" /usr/bin/env -i HOME=/root PATH=/usr/sbin:/usr/bin:/sbin:/bin TERM=dumb bash -c "$1"; }
stamp() {  # prefixes each line with the seconds since $1
    local t0=$1 line now
    while IFS= read -r line; do
        now=$EPOCHREALTIME; local d=$(( (${now/./} - ${t0/./}) / 100000 ))
        printf '%5d.%d %s\n' $((d / 10)) $((d % 10)) "$line"
    done
}

mkdir -p "$work"
if [ ! -f "$work/base.tar" ]; then
    echo "fresh_debian: debootstrap --variant=minbase bookworm ($mirror)"
    rm -rf "$work/base"
    debootstrap --variant=minbase bookworm "$work/base" "$mirror" >"$work/debootstrap.log" 2>&1 ||
        { echo "fresh_debian: debootstrap failed (see $work/debootstrap.log)" >&2; exit 1; }
    printf 'deb %s bookworm main\ndeb %s bookworm-updates main\ndeb http://deb.debian.org/debian-security bookworm-security main\n' \
        "$mirror" "$mirror" >"$work/base/etc/apt/sources.list"
    cp /etc/resolv.conf "$work/base/etc/resolv.conf"
    tar -C "$work/base" -cf "$work/base.tar" . && rm -rf "$work/base"
fi

# 1. The quickstart, timed.
fresh
rm -rf "$work/clone" && git clone -q "$src" "$work/clone" && cp -a "$work/clone" "$root/root/rayfarm"
echo "fresh_debian: quickstart of $(git -C "$src" rev-parse --short HEAD) on $(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg)"
t0=$EPOCHREALTIME
set +e
in_root 'cd /root/rayfarm && bash examples/quickstart.sh' 2>&1 | stamp "$t0" >"$work/quickstart.log"
rc=${PIPESTATUS[0]}
set -e
t1=$EPOCHREALTIME
total=$(( (${t1/./} - ${t0/./}) / 1000000 ))
phase() { grep -m1 -E "$1" "$work/quickstart.log" | awk '{print $1}'; }
echo "fresh_debian: quickstart exit $rc in ${total} s (install until $(phase '^ *[0-9.]+ -- The CXX') s," \
     "built at $(phase 'Built target rayfarm$') s, demo film written at $(phase 'wrote out/engine_turntable.mp4') s)"
[ "$rc" -eq 0 ] || { tail -20 "$work/quickstart.log"; exit 1; }
grep -m1 'sustained' "$work/quickstart.log" || true

# 2. The package.
in_root 'cd /root/rayfarm/build && cpack -G DEB >/root/cpack.log 2>&1' || { tail -20 "$root/root/cpack.log"; exit 1; }
deb=$(cd "$root/root/rayfarm/build" && ls rayfarm_*.deb)
cp "$root/root/rayfarm/build/$deb" "$work/$deb"
echo "fresh_debian: $deb depends on: $(dpkg-deb -f "$work/$deb" Depends)"

# 3. Installed on a second fresh machine, run from PATH, alone and under mpirun.
fresh
cp "$work/$deb" "$root/root/"
cp "$src/scenes/whitted.json" "$root/root/"
in_root "export DEBIAN_FRONTEND=noninteractive; apt-get update -qq && apt-get install -y -qq ./root/$deb >/root/apt.log 2>&1" ||
    { tail -20 "$root/root/apt.log"; exit 1; }
in_root 'cd /root && command -v rayfarm && rayfarm --version && man -w rayfarm 2>/dev/null; ls /usr/share/man/man1/rayfarm.1*' 
in_root 'cd /root && rayfarm render whitted.json -o one.mp4 --frames 0:5 --size 160x90 2>&1 | tail -1 &&
         OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 mpirun -np 2 --oversubscribe rayfarm render whitted.json -o two.mp4 --frames 0:5 --size 160x90 2>&1 | tail -1 &&
         cmp one.mp4.frames/frame_000005.png two.mp4.frames/frame_000005.png && echo "same frames alone and under mpirun -np 2"'
echo "fresh_debian: ok"
