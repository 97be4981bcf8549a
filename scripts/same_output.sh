#!/usr/bin/env bash
# Run each command of hipsim on the built-in cycle and keep what it writes, so
# that two versions can be compared byte for byte:
#   scripts/same_output.sh OUTDIR            (with the hipsim on PATH / PYTHONPATH)
#   diff -r OLD_OUTDIR NEW_OUTDIR
# Reports (HTML, figures) carry no dates; anything that names a time or a path
# is left out on purpose.
set -u
out=${1:?usage: same_output.sh OUTDIR}
mkdir -p "$out"
MODELS=$(python -c "import hipsim.models, os; print(os.path.dirname(hipsim.models.__file__))")
cd "$out"
run() { name=$1; shift; "$@" >"$name.stdout" 2>"$name.stderr"; echo $? >"$name.rc"; }
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
