#!/usr/bin/env bash
# Regenerates the pictures of README.md and docs/pictures.md (run from the repository root
# after `make build`). The runs take a few seconds each (the ts one about a minute). The
# PNGs are then reduced to 256 colours with Debian's python3-pil (not installed by
# scripts/setup: only needed here) to keep each under 300 kB.
set -euo pipefail
B=build/bin/ballagg
W=$(mktemp -d)
trap 'rm -rf "$W"' EXIT
common=(--set system.n=10000 --set system.boundary=periodic --set system.volume_fraction=0.2 --set stop.clusters=150 --seed 2)
$B run -q --out "$W/ed2d" "${common[@]}"
OMP_NUM_THREADS=1 $B run -q --out "$W/ts2d" --set engine.kind=ts "${common[@]}"
$B run -q --out "$W/ed3d" --set system.dimension=3 --set system.n=6000 --set system.boundary=periodic \
  --set system.volume_fraction=0.1 --set stop.clusters=80 --seed 3
$B run -q --out "$W/agg3d" --set system.dimension=3 --set system.n=2000 --set system.boundary=periodic \
  --set system.volume_fraction=0.05 --seed 4
# Richardson's (1995) model (v) with the rigid-body engine (about 10 s): its largest
# aggregate at T = 40.8, as his ray-traced Fig. 12.
$B run -q --out "$W/rb" examples/richardson1995/model-v.toml
$B render "$W/ed2d" --png docs/images/ed_2d.png --width 640
$B render "$W/ts2d" --png docs/images/ts_2d.png --width 640
$B render "$W/ed3d" --png docs/images/ed_3d_box.png --width 640
$B render "$W/agg3d" --png docs/images/ed_3d_aggregate.png --pov "$W/aggregate.pov" --width 640
povray +W640 +H640 +A0.3 -D -V +O"docs/images/ed_3d_aggregate_povray.png" "$W/aggregate.pov" 2>/dev/null
$B render "$W/rb" --aggregate 1 --png docs/images/rigid_body_aggregate.png --pov "$W/rb.pov" --width 640
povray +W640 +H640 +A0.3 -D -V +O"docs/images/rigid_body_aggregate_povray.png" "$W/rb.pov" 2>/dev/null
# ParaView (optional: Debian's paraview, python3-paraview and xvfb): examples/paraview/
# view_run.py on a 2D run's trajectory, frame 8 (t = 16).
if command -v pvpython >/dev/null && command -v xvfb-run >/dev/null; then
  $B run -q --out "$W/pv2d" --set system.n=2000 --set system.boundary=periodic \
    --set output.snapshot_every=2 --set stop.clusters=20 --seed 2
  xvfb-run -a -s "-screen 0 1024x768x24" pvpython examples/paraview/view_run.py "$W/pv2d" --frame 8 \
    --screenshot docs/images/paraview_2d.png --width 640
fi
for f in docs/images/*.png; do
  /usr/bin/python3 -c "import sys; from PIL import Image
Image.open(sys.argv[1]).convert('RGB').quantize(256, method=Image.Quantize.MEDIANCUT, dither=Image.Dither.NONE).save(sys.argv[1], optimize=True)" "$f"
done
ls -l docs/images/*.png
