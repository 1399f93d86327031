#!/usr/bin/env bash
# Seeds each fuzz target's corpus (fuzz/corpus/TARGET) from the project's own inputs: scenes,
# body files and meshes, 2D scenes and images, golden traces and a dumped contact problem.
# Run from the repository root: fuzz/seed.sh; then cargo +nightly fuzz run TARGET.
set -euo pipefail
cd "$(dirname "$0")/.."
c=fuzz/corpus
mkdir -p $c/scene3d $c/world3d $c/obj $c/scene2d $c/png $c/trace $c/problem $c/compare $c/siconos
for s in scenes/*.json; do
  root=$(python3 -c "import json,sys; print(json.load(open('$s'))['bodies'][0]['file_root'])")
  body=scenes/$root
  [ -f "$body.json" ] || continue
  { cat "$s"; printf '\xff'; cat "$body.json"; printf '\xff'; cat "$body.obj"; } > "$c/scene3d/$(basename "$s" .json)"
  # world3d makes worlds of meshes of at most 64 vertices only
  if [ "$(grep -c '^v ' "$body.obj")" -le 64 ]; then cp "$c/scene3d/$(basename "$s" .json)" "$c/world3d/"; fi
done
for o in scenes/data/*.obj; do
  [ "$(stat -c %s "$o")" -lt 100000 ] && cp "$o" "$c/obj/"
done
cp scenes/blocks/*.json $c/scene2d/
cp scenes/blocks/*.png $c/png/
for g in golden/*.jsonl; do
  head -c 60000 "$g" | head -n 20 > "$c/trace/$(basename "$g")"
done
for g in box_stack projectile sliding_cube; do
  { head -n 30 golden/$g.jsonl; printf '\xff'; head -n 25 golden/$g.jsonl; } > "$c/compare/$g"
done
tmp=$(mktemp -d)
cargo run --release -q -- run scenes/box_stack.json --steps 2 --quiet --out "$tmp/t.jsonl" --dump-problems "$tmp/p"
cp "$tmp"/p/*.json $c/problem/ 2>/dev/null || true
rm -rf "$tmp"
echo "seeded: $(ls $c/* | wc -l) files"
# Siconos' small problems (every storage the 3D ones use), and a local-form problem file
cp tests/data/siconos/*.dat $c/siconos/
cargo run --release -q -- convert-problem tests/data/siconos/Rover4396.dat "$c/problem/rover4396-local.json"
