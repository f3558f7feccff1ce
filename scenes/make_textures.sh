#!/usr/bin/env bash
# Usage: scenes/make_textures.sh OUTDIR [SIZE] [COUNT]
# Writes COUNT procedural colour textures of SIZE x SIZE texels (default 8192, 4) into OUTDIR as
# tiled, MIP-mapped half-float OpenEXR files (tex0.tx, tex1.tx, ...) that the renderer reads in
# place (docs/scene-format.md, "Texture files"): a checkerboard of two colours per texture
# times Gaussian noise, so every MIP level differs. Not committed: a scene that needs them, or a
# bench, makes them into the build tree. An 8192 texture is 512 MiB of half-float texels with
# its MIP levels; oiiotool holds one float copy of it while writing (768 MiB).
set -euo pipefail
[ $# -ge 1 ] || { echo "usage: scenes/make_textures.sh OUTDIR [SIZE] [COUNT]" >&2; exit 2; }
out=$1; size=${2:-8192}; count=${3:-4}
command -v oiiotool >/dev/null || { echo "make_textures: oiiotool not found (openimageio-tools: scripts/setup)" >&2; exit 1; }
mkdir -p "$out"
colors=("0.8,0.3,0.2" "0.2,0.6,0.3" "0.25,0.35,0.8" "0.9,0.8,0.3" "0.6,0.6,0.6" "0.7,0.4,0.7")
for ((k = 0; k < count; ++k)); do
  f="$out/tex$k.tx"
  [ -f "$f" ] && continue  # already made (same name, same size: delete to remake)
  c1=${colors[$((k % ${#colors[@]}))]}
  c2=${colors[$(((k + 3) % ${#colors[@]}))]}
  check=$((size / 16))
  oiiotool --pattern checker:width=$check:height=$check:color1=$c1:color2=$c2 ${size}x${size} 3 \
    --pattern noise:type=gaussian:mean=1:stddev=0.15:seed=$k ${size}x${size} 3 --mul \
    -d half --tile 64 64 -otex "$f.tmp.exr"
  mv "$f.tmp.exr" "$f"
  echo "make_textures: $f" >&2
done
