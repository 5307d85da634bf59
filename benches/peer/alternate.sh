#!/bin/sh
# Runs elasto and the peer (peer_ipc.py) on the box stack alternately, one thread each, and prints
# the trajectory comparison and the medians. See README.md beside this file.
#
#   benches/peer/alternate.sh ELASTO_BINARY VENV_PYTHON RUNS OUT_FOLDER
set -eu
elasto=$1 python=$2 runs=$3 out=$4
here=$(dirname "$0")
scene=$here/box-stack-12k.toml
mkdir -p "$out"
# elasto's own run with its meshes: the tetrahedra the peer reads and the trajectory it is held to.
"$elasto" run "$scene" --no-render --save-meshes -q --force -o "$out/reference"
i=1
while [ "$i" -le "$runs" ]; do
    RAYON_NUM_THREADS=1 /usr/bin/time -f "%e %U %S" -o "$out/elasto-$i.time" \
        "$elasto" run "$scene" --no-render -q --force -o "$out/elasto-$i"
    /usr/bin/time -f "%e %U %S" -o "$out/peer-$i.time" \
        "$python" "$here/peer_ipc.py" run "$out/reference" "$out/peer-$i" --threads 1 2>/dev/null
    i=$((i + 1))
done
"$python" "$here/peer_ipc.py" compare "$out/reference" "$out/peer-1"
"$python" "$here/peer_ipc.py" summary "$out"
