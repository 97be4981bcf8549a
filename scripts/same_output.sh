#!/usr/bin/env bash
# Run each command of hipsim on the built-in cycle and keep what it writes, so
# that two versions can be compared byte for byte:
#   scripts/same_output.sh OUTDIR            (with the hipsim on PATH / PYTHONPATH)
#   diff -r OLD_OUTDIR NEW_OUTDIR
# Figures (PNG, SVG) are left out: their bytes depend on the matplotlib build.
set -u
out=${1:?usage: same_output.sh OUTDIR}
mkdir -p "$out"
MODELS=$(python -c "import hipsim.models, os; print(os.path.dirname(hipsim.models.__file__))")
cd "$out"
# Timings and the numba compile notes of a cold cache are left out of the text outputs.
run() {
  name=$1; shift
  "$@" >"$name.stdout" 2>"$name.stderr"; echo $? >"$name.rc"
  sed -i -E '/compiling \(first run only\)/d; s/in [0-9]+\.[0-9]+ s/in (time) s/' "$name.stdout" "$name.stderr"
}
run torques hipsim torques --out torques.csv
run torques_pin hipsim torques --model pinocchio --out torques_pin.csv
run torques_mj hipsim torques --model mujoco --out torques_mj.csv
run check hipsim check
run check_mj hipsim check --engine mujoco
run simulate hipsim simulate --out simulate.csv
run simulate_pin hipsim simulate --plant pinocchio --cycles 0.2 --out simulate_pin.csv
run params hipsim params
run size hipsim size
run size_cat hipsim size --catalogue "$MODELS/motors_example.csv" --screws "$MODELS/screws_example.csv" --gearboxes "$MODELS/gearboxes_example.csv"
run urdf hipsim urdf --out model.urdf
run mjcf hipsim mjcf --out model.xml
run workspace hipsim workspace --out ws
run excite hipsim excite --out excite.csv
run report hipsim report --out report
rm -f report/*.png report/*.svg ws/*.png ws/*.svg
