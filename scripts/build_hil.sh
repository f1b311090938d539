#!/usr/bin/env bash
# Build everything a HIL rig needs, in one command, into OUT (default out/hil):
#   OUT/pcsim_fmu.fmu        FMI 2.0 co-simulation FMU
#   OUT/pcsim_fmu_fmi3.fmu   FMI 3.0 co-simulation FMU
#   OUT/c/include/pcsim.h, OUT/c/lib/libpcsim_capi.{so,a}   the C API
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-out/hil}
cargo build --release --locked
./target/release/pcsim fmu build --out "$out"
mkdir -p "$out/c/include" "$out/c/lib"
cp include/pcsim.h "$out/c/include/"
cp target/release/libpcsim_capi.so target/release/libpcsim_capi.a "$out/c/lib/"
echo "C API: $out/c (cc my_loop.c -I$out/c/include -L$out/c/lib -lpcsim_capi)"
