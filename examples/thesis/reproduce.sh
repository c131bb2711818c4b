#!/usr/bin/env bash
# Reproduce thesis chapter 6 with flexflight: the planar stability maps behind Figs 6.3-6.8,
# the 3-D boundary of Fig 6.11 (from the linearised 3-D model, at the scenario's altitude),
# the six flights of Tables 6.1-6.2, and a run sweep over fin thickness and speed; each with
# its figures (DIR/report/index.html). Usage: examples/thesis/reproduce.sh [OUT] (default
# out/thesis). Takes a few minutes on two cores; the sweep is the long part.
set -euo pipefail
cd "$(dirname "$0")/../.."
OUT=${1:-out/thesis}
F=examples/thesis/section_6_5.vdl
cargo build --release --quiet
FF=target/release/flexflight

# Figs 6.3-6.5: pinned planar model at 0, 10 and 20 km.
for h in 0 10000 20000; do
  d=$OUT/fig6_3-5_pinned_h${h}m
  $FF analyze map --planar --pinned $F --scenario subsonic_t06 \
    --thickness 0.1mm:1.5mm:29 --mach 0.2:3.0:29 --altitude ${h}m --out "$d"
  $FF report "$d"
done

# Fig 6.7: unpinned planar model at its terminal-velocity equilibrium altitude (no
# equilibrium below about Mach 0.65: those points are recorded as failures).
d=$OUT/fig6_7_unpinned
$FF analyze map --planar --unpinned $F --scenario subsonic_t06 \
  --thickness 0.1mm:1.5mm:29 --mach 0.7:3.0:24 --out "$d"
$FF report "$d"

# Fig 6.8: pinned model at the unpinned model's equilibrium altitudes.
d=$OUT/fig6_8_pinned_equilibrium
$FF analyze map --planar --pinned $F --scenario subsonic_t06 \
  --thickness 0.1mm:1.5mm:29 --mach 0.7:3.0:24 --altitude equilibrium --out "$d"
$FF report "$d"

# Fig 6.11 (our substitute): the linearised 3-D model's boundary at 5 km.
d=$OUT/fig6_11_linear3d_5km
$FF analyze linear-map $F --scenario subsonic_t06 --thickness 0.3mm:1.5mm:13 --mach 0.3:1.0:15 \
  --out "$d"
$FF report "$d"

# Tables 6.1-6.2: the six flights of 6.5, with their figures and deformation frames.
for s in subsonic_t03 subsonic_t04 subsonic_t06 supersonic_t06 supersonic_t07 supersonic_t10; do
  $FF run $F --scenario $s --out "$OUT/$s"
  $FF report "$OUT/$s" --vehicle-file $F
done

# The run sweep of section_6_5.vdl: fin thickness x speed, every case flown.
$FF sweep $F --sweep subsonic_thickness --out "$OUT/sweep_subsonic_thickness"
# The same thicknesses through the linearised 3-D and the planar pinned models.
$FF sweep $F --sweep subsonic_thickness_linear --out "$OUT/sweep_subsonic_thickness_linear"
$FF sweep $F --sweep subsonic_thickness_planar --out "$OUT/sweep_subsonic_thickness_planar"
echo "done: $OUT"
