#!/bin/sh
# doc-pictures.sh [LANCER]: renders the small picture of each example that
# the README's table shows, docs/examples/NN_name.png, 160 pixels wide (each
# at its script's own aspect ratio and samples). Run from the repository's
# top after `make`; remake them whenever an example or the renderer changes.
set -eu
lancer=${1:-build/bin/lancer}
out=docs/examples
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$out"

still() {                       # still NAME HEIGHT [ARGS...]: a script saving arg[1]
    name=$1 height=$2
    shift 2
    "$lancer" --width 160 --height "$height" "examples/$name.lua" "$out/$name.png" "$@" \
        >/dev/null
}

frame() {                       # frame NAME N: frame N of a lancer.animate script
    "$lancer" --width 160 --height 120 --frame "$2" -o "$tmp/$1_####.png" \
        "examples/$1.lua" 2>/dev/null
    mv "$tmp/$1_$(printf %04d "$2").png" "$out/$1.png"
}

still 01_first_sphere 120
still 02_materials 120
still 03_lights_and_shadows 120
still 04_procedural 120
"$lancer" --width 160 --height 120 examples/05_frames.lua "$tmp/frames" >/dev/null
mv "$tmp/frames/frame_0003.png" "$out/05_frames.png"
frame 06_orbit 7
frame 07_wave 10
still 08_moving 107
still 09_soft_glossy_lens 90
still 10_glass 100
still 11_csg 107
still 12_textures 100
still 13_obj_mtl 100
still 14_shapes 100
still 15_lights_and_sky 100
ls -l "$out"
