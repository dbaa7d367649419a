#!/bin/sh
# Build kerikun11/micromouse-maze-library (the C++ library micromouse users compare mazelog with) from source at a
# pinned commit, with scripts/kerikun/maze_timing.cpp linked against it, for scripts/benchmark_maze_kernel.py.
# Never vendored: SOURCE is a checkout, a bare mirror or a git URL, cloned into OUT (default build/kerikun).
#
#   scripts/build_maze_library.sh SOURCE [OUT]
#   e.g. scripts/build_maze_library.sh https://github.com/kerikun11/micromouse-maze-library.git
#
# The pin is the develop branch's head when the comparison was first measured (docs/BENCHMARKS.md); its
# submodule (the maze data) is not needed. Needs git and a C++17 compiler ($CXX, else c++).
set -eu
COMMIT=cec2b9cc655e592de6fad06391271370bd377d78
[ $# -ge 1 ] && [ $# -le 2 ] || { echo "usage: $0 SOURCE [OUT]" >&2; exit 2; }
SOURCE=$1
HERE=$(cd "$(dirname "$0")" && pwd)
OUT=${2:-$HERE/../build/kerikun}
CXX=${CXX:-c++}
command -v git >/dev/null || { echo "$0: git is not on PATH" >&2; exit 1; }
command -v "$CXX" >/dev/null || { echo "$0: no C++ compiler ($CXX); install g++ or set CXX" >&2; exit 1; }
mkdir -p "$OUT"
OUT=$(cd "$OUT" && pwd)
if [ ! -d "$OUT/src/.git" ]; then
    rm -rf "$OUT/src"
    git clone --quiet --no-checkout "$SOURCE" "$OUT/src"
fi
git -C "$OUT/src" -c advice.detachedHead=false checkout --quiet "$COMMIT"
mkdir -p "$OUT/obj"
for f in "$OUT"/src/src/*.cpp; do
    "$CXX" -std=c++17 -O2 -DNDEBUG -I"$OUT/src/include" -c "$f" -o "$OUT/obj/$(basename "$f" .cpp).o"
done
"$CXX" -std=c++17 -O2 -DNDEBUG -I"$OUT/src/include" "$HERE/kerikun/maze_timing.cpp" "$OUT"/obj/*.o \
    -o "$OUT/maze_timing"
echo "$OUT/maze_timing (micromouse-maze-library $COMMIT)"
