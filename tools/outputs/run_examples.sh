#!/usr/bin/env bash
# outputs.sh BIN OUT: every example's outputs with BIN, into OUT (a fresh cache per call).
BIN=$1; OUT=$2; rm -rf $OUT; mkdir -p $OUT; C=$OUT/cache
cd "$(dirname "$0")/../.."
r() { name=$1; shift; "$BIN" "$@" --cache-dir $C > $OUT/$name.stdout 2> $OUT/$name.stderr; echo $? > $OUT/$name.rc; }
r k1000 run examples/hpr_k1000/hpr_k1000.vdl --scenario k1000 --out $OUT/k1000
r m1670 run examples/hpr_k1000/hpr_k1000.vdl --scenario m1670 --out $OUT/m1670
r calisto run examples/calisto/calisto.vdl --scenario calisto --out $OUT/calisto
r m4fin run examples/m1670_4fin/m1670_4fin.vdl --scenario flight --out $OUT/m4fin
r t06 run examples/thesis/section_6_5.vdl --scenario subsonic_t06 --out $OUT/t06
r t06json run examples/thesis/section_6_5.vdl --scenario subsonic_t06 --out $OUT/t06j --format json
r tumble run examples/free_tumble.vdl --scenario free_tumble --out $OUT/tumble
r plan_k1000 plan examples/hpr_k1000/hpr_k1000.vdl --scenario k1000
r plan_t06 plan examples/thesis/section_6_5.vdl --scenario subsonic_t06 --format json
r fl_clamped analyze flutter examples/hpr_k1000/hpr_k1000.vdl --scenario k1000 --clamped --mach 0.6 --out $OUT/fl_clamped
r fl_free analyze flutter examples/thesis/section_6_5.vdl --scenario subsonic_t06 --out $OUT/fl_free
r fl_match analyze flutter examples/hpr_k1000/hpr_k1000.vdl --scenario k1000 --clamped --match-point
r fl_crit analyze flutter examples/hpr_k1000/hpr_k1000.vdl --scenario k1000 --clamped --mach 0.6 --critical-thickness 1mm:4mm:4 --target-speed 250m/s
r agard analyze flutter examples/agard445/agard445.vdl --scenario m0499 --out $OUT/agard
r planar analyze planar --pinned examples/thesis/section_6_5.vdl --scenario subsonic_t06
r linear analyze linear examples/thesis/section_6_5.vdl --scenario subsonic_t06
r sweep sweep examples/thesis/section_6_5.vdl --sweep subsonic_thickness_planar --out $OUT/sweep --jobs 2
r report report $OUT/k1000
r unknown run examples/hpr_k1000/hpr_k1000.vdl --scenario nope --out $OUT/nope
r check check examples/hpr_k1000/hpr_k1000.vdl --format json
"$BIN" compile examples/hpr_k1000/hpr_k1000.vdl --cache-dir $C --format json | grep -v '"seconds"\|"cache"' > $OUT/compile.json
"$BIN" inspect $(ls $C/*.ffa | head -1) > $OUT/inspect.txt 2>&1
rm -rf $C
