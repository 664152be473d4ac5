#!/usr/bin/env bash
# rayfarm under Slurm, the scheduler HPC users run: `RAYFARM_SLURM=1 bash tests/slurm/run.sh
# [RAYFARM] [WORK_DIR]`. Opt-in (exits 77, skipped, without RAYFARM_SLURM=1): it installs
# Debian's munge, slurmctld, slurmd and slurm-client if missing, and starts them on localhost
# with every file (key, sockets, state, logs, config) in one temporary directory:
#   1. examples/slurm/turntable.sbatch through sbatch: the video holds every frame and is
#      byte-identical to one process rendering the same film (--lossless);
#   2. scancel (SIGTERM to every process of the job) mid-film: the log says interrupted, names
#      the resume command, and the partial video plays the frames finished;
#   3. the same script submitted again with --resume: byte-identical to the uninterrupted run;
#   4. examples/slurm/turntable-srun.sbatch (srun --no-kill as the launcher, 3 tasks) with one
#      task (rank 2) killed with kill -9 mid-film: either the film completes, byte-identical to
#      one process's, or (Slurm 22.05's mpi/pmix plugin) the step is ended, which it says, and
#      the script submitted again with --resume completes the film byte for byte;
#   5. examples/slurm/turntable-keep-going.sbatch (mpirun --enable-recovery, sbatch --no-kill),
#      3 ranks, rank 2 killed with kill -9 mid-film: the film completes, byte for byte.
# Stops every daemon it started and removes the directory, even when a step fails.
set -euo pipefail
SRC=$(cd "$(dirname "$0")/../.." && pwd)
RAYFARM=$(realpath "${1:-$SRC/build/bin/rayfarm}")
WORK=${2:-$SRC/build/test-output/slurm}
SCRIPT=$SRC/examples/slurm/turntable.sbatch
SRUN_SCRIPT=$SRC/examples/slurm/turntable-srun.sbatch
MODEL=/usr/share/assimp/models/glTF2/BoxTextured-glTF/BoxTextured.gltf

if [ "${RAYFARM_SLURM:-0}" != 1 ]; then
    echo "slurm: skipped (opt-in: RAYFARM_SLURM=1; starts munge and Slurm daemons on localhost)" >&2
    exit 77
fi
[ "$(id -u)" -eq 0 ] || { echo "slurm: skipped: needs root to install and start the daemons" >&2; exit 77; }
fail() { echo "FAIL: $*" >&2; exit 1; }

# Debian's packages, installed here rather than by install-deps.sh: only this opt-in test needs them.
if ! command -v slurmctld > /dev/null || ! command -v slurmd > /dev/null || ! command -v sbatch > /dev/null ||
   ! command -v munged > /dev/null; then
    export DEBIAN_FRONTEND=noninteractive
    apt-get install -y --no-install-recommends slurmctld slurmd slurm-client munge > /dev/null ||
        { apt-get update > /dev/null && apt-get install -y --no-install-recommends slurmctld slurmd slurm-client munge > /dev/null; } ||
        fail "cannot install munge and Slurm from Debian"
fi

export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 HWLOC_COMPONENTS=-gl
T=$(mktemp -d /tmp/rayfarm-slurm.XXXXXX)
chmod 700 "$T"
daemons=()
cleanup() {
    local rc=$? pid
    [ -n "${SLURM_CONF:-}" ] && scancel --quiet --user=root 2> /dev/null || true
    for pid in "${daemons[@]}"; do kill "$pid" 2> /dev/null || true; done
    for pid in "${daemons[@]}"; do
        for _ in $(seq 50); do kill -0 "$pid" 2> /dev/null || break; sleep 0.1; done
        kill -9 "$pid" 2> /dev/null || true
    done
    if [ $rc -ne 0 ]; then
        for log in "$T"/*.log; do [ -f "$log" ] && { echo "--- $log"; tail -20 "$log"; } >&2; done
    fi
    rm -rf "$T"
    exit $rc
}
trap cleanup EXIT
trap 'exit 130' INT
trap 'exit 143' TERM

# munge, with its own key and socket.
dd if=/dev/urandom of="$T/munge.key" bs=1024 count=1 status=none
chmod 400 "$T/munge.key"
munged --foreground --force --key-file="$T/munge.key" --socket="$T/munge.sock" --pid-file="$T/munged.pid" \
    --log-file="$T/munged.log" --seed-file="$T/munged.seed" 2> "$T/munged.err" &
daemons+=($!)

# Two free TCP ports on loopback for slurmctld and slurmd.
read -r ctld_port slurmd_port < <(python3 -c '
import socket
s = [socket.socket() for _ in range(2)]
for x in s: x.bind(("127.0.0.1", 0))
print(*(x.getsockname()[1] for x in s))')
mkdir -p "$T/state" "$T/spool"
export SLURM_CONF=$T/slurm.conf
# CPUs=4 on this 2-core machine (config_overrides): steps 4 and 5 run 3 tasks.
cat > "$SLURM_CONF" <<CONF
ClusterName=rayfarmtest
SlurmctldHost=localhost(127.0.0.1)
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$T/munge.sock
StateSaveLocation=$T/state
SlurmdSpoolDir=$T/spool
SlurmctldPidFile=$T/slurmctld.pid
SlurmdPidFile=$T/slurmd.pid
SlurmctldLogFile=$T/slurmctld.log
SlurmdLogFile=$T/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
MpiDefault=none
SchedulerType=sched/builtin
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
ReturnToService=2
SlurmdParameters=config_overrides
KillWait=10
NodeName=localhost NodeAddr=127.0.0.1 CPUs=4 State=UNKNOWN
PartitionName=test Nodes=localhost Default=YES MaxTime=INFINITE State=UP
CONF
for _ in $(seq 50); do [ -S "$T/munge.sock" ] && break; sleep 0.1; done
[ -S "$T/munge.sock" ] || fail "munged did not start: $(cat "$T/munged.err")"
slurmctld -D -f "$SLURM_CONF" 2> "$T/slurmctld.err" &
daemons+=($!)
slurmd -D -N localhost -f "$SLURM_CONF" 2> "$T/slurmd.err" &
daemons+=($!)
for _ in $(seq 100); do
    state=$(sinfo -h -N -o %t 2> /dev/null || true)
    [ "$state" = idle ] && break
    sleep 0.2
done
[ "$state" = idle ] || fail "the Slurm node did not come up (state: '$state')"
echo "slurm: munged, slurmctld and slurmd up on localhost (ports $ctld_port, $slurmd_port)"

mkdir -p "$WORK"
cd "$WORK"
rm -rf full.* part.* ref.* keep.* keepref.* keepres.* going.*
probe() {  # file -> frames
    ffprobe -v error -select_streams v:0 -count_frames -show_entries stream=nb_read_frames -of csv=p=0 "$1"
}
film=(--size 96x72 --frames 0:35 --spp 16 --lossless)
export RAYFARM
"$RAYFARM" render "$MODEL" -o ref.mp4 --no-frames "${film[@]}" 2> ref.log || { cat ref.log; fail "reference run failed"; }

# 1. A whole film.
sbatch --wait --quiet -o full.log "$SCRIPT" "$MODEL" full.mp4 "${film[@]}" || { cat full.log; fail "the sbatch job failed"; }
grep -q "rayfarm: wrote full.mp4: 36 frames" full.log || { cat full.log; fail "the job did not write the video"; }
grep -q "2 ranks" full.log || { cat full.log; fail "mpirun did not start one rank per Slurm task"; }
[ "$(probe full.mp4)" = 36 ] || fail "full.mp4 has $(probe full.mp4) frames, expected 36"
cmp -s full.mp4 ref.mp4 || fail "the video of the Slurm job differs from one process's"
echo "slurm: sbatch rendered 36 frames on 2 ranks, byte-identical to one process"

# 2. scancel mid-film.
slow=(--size 96x72 --frames 0:59 --spp 64 --lossless)
"$RAYFARM" render "$MODEL" -o ref.mp4 --no-frames "${slow[@]}" 2> ref.log || { cat ref.log; fail "reference run failed"; }
job=$(sbatch --parsable -o part.log "$SCRIPT" "$MODEL" part.mp4 "${slow[@]}")
for _ in $(seq 600); do
    [ "$(ls part.mp4.frames 2> /dev/null | grep -c '^frame_.*\.png$')" -ge 6 ] && break
    sleep 0.1
done
[ "$(ls part.mp4.frames 2> /dev/null | grep -c '^frame_.*\.png$')" -ge 6 ] || { cat part.log; fail "the job made fewer than 6 frames in 60 s"; }
start=$EPOCHREALTIME
scancel "$job"
for _ in $(seq 300); do [ -z "$(squeue -h -j "$job" 2> /dev/null)" ] && break; sleep 0.1; done
[ -z "$(squeue -h -j "$job" 2> /dev/null)" ] || fail "job $job still queued 30 s after scancel"
took=$(awk -v a="$start" -v b="$EPOCHREALTIME" 'BEGIN { printf "%.1f", b - a }')
if pgrep -f "render $MODEL -o part.mp4" > /dev/null; then fail "rayfarm processes left after scancel"; fi
grep -q "rayfarm: interrupted (SIGTERM): the video part.mp4 holds .* (playable)" part.log || { cat part.log; fail "no interrupted line after scancel"; }
grep -q "^rayfarm: to resume: mpirun .*--resume$" part.log || { cat part.log; fail "no resume command after scancel"; }
frames=$(probe part.mp4)
kept=$(ls part.mp4.frames | grep -c '^frame_.*\.png$')
[ -n "$frames" ] && [ "$frames" -ge 1 ] && [ "$frames" -le "$kept" ] || fail "after scancel part.mp4 plays '$frames' frames ($kept PNGs)"
echo "slurm: scancel stopped the job in $took s; $(grep 'rayfarm: interrupted' part.log | cut -d: -f3-); it plays $frames frames"

# 3. The same script again, with --resume.
sbatch --wait --quiet -o resume.log "$SCRIPT" "$MODEL" part.mp4 "${slow[@]}" --resume || { cat resume.log; fail "the resume job failed"; }
grep -q "frames kept in part.mp4.frames" resume.log || { cat resume.log; fail "the resume job kept no frames"; }
cmp -s part.mp4 ref.mp4 || fail "the resumed video differs from one uninterrupted run"
echo "slurm: --resume after scancel gave a video byte-identical to an uninterrupted run"

# 4. srun --no-kill, one task killed with kill -9 mid-film. Slurm 22.05's mpi/pmix plugin
# (Debian 12) ends the whole step when a task dies, whatever --no-kill and --kill-on-bad-exit
# say: its PMIx error handler calls slurm_kill_job_step(SIGKILL) ("mpi/pmix_v4: _errhandler:
# ... Error handler invoked", then "STEP N.0 ... CANCELLED"). This step says which happened:
# the film completed on the others (checked byte for byte), or the step was ended that way
# (said as such; the script submitted again with --resume then completes the film byte for
# byte).
keep=(--size 96x72 --frames 0:119 --spp 64 --lossless --chunk-frames 6 --mode frame --timeout 4)
"$RAYFARM" render "$MODEL" -o keepref.mp4 --no-frames "${keep[@]}" 2> keepref.log || { cat keepref.log; fail "reference run failed"; }
kill_task_mid_film() {  # job out rank-variable: kill -9 of that rank once 6 frames are done
    local job=$1 out=$2 key=$3 p env victim=""
    for _ in $(seq 600); do
        [ "$(ls "$out.frames" 2> /dev/null | grep -c '^frame_.*\.png$')" -ge 6 ] && break
        sleep 0.1
    done
    [ "$(ls "$out.frames" 2> /dev/null | grep -c '^frame_.*\.png$')" -ge 6 ] || return 1
    for p in $(pgrep -x rayfarm); do
        env=$(tr '\0' '\n' < /proc/"$p"/environ 2> /dev/null || true)
        grep -qx "SLURM_JOB_ID=$job" <<<"$env" && grep -qx "$key=2" <<<"$env" && victim=$p
    done
    [ -n "$victim" ] || return 1
    kill -9 "$victim"
}
wait_job() {  # job: until it leaves the queue (120 s)
    for _ in $(seq 1200); do [ -z "$(squeue -h -j "$1" 2> /dev/null)" ] && return 0; sleep 0.1; done
    return 1
}
check_film() {  # log out what
    grep -q "^rayfarm: wrote $2: 120 frames" "$1" || { cat "$1"; fail "$3: the film did not complete"; }
    [ "$(probe "$2")" = 120 ] || fail "$3: $2 has $(probe "$2") frames, expected 120"
    cmp -s "$2" keepref.mp4 || fail "$3: $2 differs from one process's film"
}
job=$(sbatch --parsable -o keep.log "$SRUN_SCRIPT" "$MODEL" keep.mp4 "${keep[@]}")
kill_task_mid_film "$job" keep.mp4 SLURM_PROCID || { cat keep.log; fail "srun job $job: task 2 not found, or fewer than 6 frames in 60 s"; }
wait_job "$job" || { cat keep.log; fail "job $job still queued 120 s after task 2 was killed"; }
echo "slurm: srun --no-kill, task 2 killed with kill -9: srun said: $(grep '^srun' keep.log | tr '\n' ' ')"
if grep -q "^rayfarm: wrote keep.mp4: 120 frames" keep.log; then
    grep -Eq "rayfarm: warning: rank 2 on [^ ]+ stopped answering" keep.log || { cat keep.log; fail "rank 0 did not name rank 2 as lost"; }
    check_film keep.log keep.mp4 "srun --no-kill"
    echo "slurm: srun --no-kill with task 2 killed mid-film: the film completed on the others, byte-identical to one process"
elif grep -q "mpi/pmix.*Error handler invoked" keep.log && grep -q "STEP $job.0 ON .* CANCELLED" "$T/slurmd.log"; then
    echo "slurm: srun --no-kill did NOT keep the step alive: Slurm's mpi/pmix plugin cancelled step $job.0 (SIGKILL to every task) when task 2 died; keep.mp4 plays $(probe keep.mp4 || echo 0) frames"
    sbatch --wait --quiet -o keepres.log "$SRUN_SCRIPT" "$MODEL" keep.mp4 "${keep[@]}" --resume || { cat keepres.log; fail "the srun resume job failed"; }
    check_film keepres.log keep.mp4 "srun --resume"
    echo "slurm: the srun script submitted again with --resume completed the film, byte-identical to one process"
else
    cat keep.log; fail "srun --no-kill with task 2 killed: neither a completed film nor the mpi/pmix step kill"
fi

# 5. What keeps a film going under Slurm: mpirun --enable-recovery inside an sbatch --no-kill
# allocation (examples/slurm/turntable-keep-going.sbatch), 3 ranks, rank 2 killed mid-film.
job=$(sbatch --parsable --ntasks=3 -o going.log "$SRC/examples/slurm/turntable-keep-going.sbatch" "$MODEL" going.mp4 "${keep[@]}")
kill_task_mid_film "$job" going.mp4 OMPI_COMM_WORLD_RANK || { cat going.log; fail "mpirun job $job: rank 2 not found, or fewer than 6 frames in 60 s"; }
wait_job "$job" || { cat going.log; fail "job $job still queued 120 s after rank 2 was killed"; }
grep -Eq "rayfarm: warning: rank 2 on [^ ]+ stopped answering" going.log || { cat going.log; fail "rank 0 did not name rank 2 as lost"; }
check_film going.log going.mp4 "mpirun --enable-recovery under sbatch --no-kill"
if pgrep -f "render $MODEL -o going.mp4" > /dev/null; then fail "rayfarm processes left after the job"; fi
echo "slurm: mpirun --enable-recovery in sbatch --no-kill, rank 2 killed mid-film: the film completed, byte-identical to one process"
echo "slurm: ok"
