# Sourced by the examples and by some benchmarks (bench/): builds rayfarm if it is missing and
# sets $bin to it. RAYFARM_BIN overrides the binary. Open MPI refuses root unless told (containers run as root).
bin=${RAYFARM_BIN:-build/bin/rayfarm}
if [ ! -x "$bin" ]; then
  bash tests/install-deps.sh
  cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
  cmake --build build -j"$(nproc 2>/dev/null || echo 2)" --target rayfarm
fi
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
