#!/usr/bin/env bash
# Builds everything, then removes the texture from the bundled example: a cube
# covered in scale-like cells (examples/textured_cube.ply, x y z only, made by
# 'detexture synth'). Writes examples/textured_cube.detextured.ply and the
# texture layer examples/textured_cube.texture.ply next to it.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
build/detexture examples/textured_cube.ply -o examples/textured_cube.detextured.ply \
  --texture-layer examples/textured_cube.texture.ply --texture-fields --force
echo "filtered cloud: $(pwd)/examples/textured_cube.detextured.ply"
echo "texture layer:  $(pwd)/examples/textured_cube.texture.ply"
