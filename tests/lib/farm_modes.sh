# Sourced by the farm's script tests (after refusal.sh): one film rendered at 1 rank in frame mode
# and at 2 and 3 ranks in frame and pixel mode, every kept frame byte-identical.

# farm_modes_identical RAYFARM MODEL ARGS...
# Runs `mpirun -np N RAYFARM render MODEL ARGS --mode M -o npN_M.mp4 --frames-dir npN_M` in the
# current directory (logs in npN_M.log) and fails naming the first frame that differs from
# np1_frame's. Leaves the frames folders for the caller's own checks.
farm_modes_identical() {
    local rayfarm=$1 model=$2 run np mode f
    shift 2
    for run in "1 frame" "2 frame" "3 frame" "2 pixel" "3 pixel"; do
        read -r np mode <<<"$run"
        mpirun --oversubscribe -np "$np" "$rayfarm" render "$model" "$@" --mode "$mode" -o "np${np}_$mode.mp4" \
            --frames-dir "np${np}_$mode" 2>"np${np}_$mode.log" || { cat "np${np}_$mode.log"; fail "render np $np $mode"; }
        [ "$run" = "1 frame" ] && continue
        for f in np1_frame/frame_*.png; do
            cmp -s "$f" "np${np}_$mode/$(basename "$f")" || fail "$(basename "$f") differs between np 1 frame mode and $run"
        done
    done
}
