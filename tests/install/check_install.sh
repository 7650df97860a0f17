#!/bin/sh
# The installed package (ctest install_embed_example, label install): `cmake --install` of the build into a
# temporary prefix, then from that prefix only:
#   1. the installed `vascsim --version` names this version and reads its bundled files from PREFIX/share/vascsim
#      (not from the source tree), and the layout has the headers, the CMake package and the scripts;
#   2. examples/embed configures with find_package(vascsim) against the prefix, builds and runs a test scene;
#   3. the installed `vascsim experiment force-displacement` on the same scene gives the same force on the tool at
#      every step (both print 9 significant digits of the same computation) and draws its plot with the
#      installed script;
#   4. the installed Python package imports from the prefix (when the module is built).
# Usage: check_install.sh CMAKE BUILD_DIR SOURCE_DIR VERSION PYTHON|none
set -eu
cmake=$1 build=$2 src=$3 version=$4 python=$5
tmp=$(mktemp -d "${TMPDIR:-/tmp}/vascsim-install-test.XXXXXX")
tmp=$(cd "$tmp" && pwd -P)
trap 'rm -rf "$tmp"' EXIT
prefix=$tmp/prefix
scene=$src/tests/data/pressed-block.json
fail() { echo "check_install: $*" >&2; exit 1; }
export OMP_NUM_THREADS=1

"$cmake" --install "$build" --prefix "$prefix" > "$tmp/install.log" || { cat "$tmp/install.log"; fail "cmake --install failed"; }

# 1. The installed command and the layout.
"$prefix/bin/vascsim" --version > "$tmp/version.txt" || fail "the installed vascsim --version failed"
cat "$tmp/version.txt"
[ "$(head -n 1 "$tmp/version.txt")" = "vascsim $version" ] || fail "the version line is not 'vascsim $version'"
grep -qx "bundled files: $prefix/share/vascsim" "$tmp/version.txt" || fail "the installed vascsim does not read PREFIX/share/vascsim"
for f in include/vascsim/run/simulation.hpp include/vascsim/core/types.hpp share/vascsim/scenes/vein-indent.json \
         share/vascsim/scripts/plot_force_displacement.py share/vascsim/data/ahp/paper-ratings.json \
         share/vascsim/data/vessels/vmtk-aorta-surface.stl; do
  [ -f "$prefix/$f" ] || fail "$f is not installed"
done
ls "$prefix"/lib*/cmake/vascsim/vascsimConfig.cmake "$prefix"/lib*/cmake/vascsim/vascsimConfigVersion.cmake > /dev/null \
  || fail "the CMake package is not installed"
[ ! -e "$prefix/include/vascsim/viewer" ] || fail "the viewer's headers are installed (not a public API)"

# 2. The example against the prefix.
"$cmake" -S "$src/examples/embed" -B "$tmp/embed" -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_BUILD_TYPE=Release \
  > "$tmp/embed-configure.log" 2>&1 || { cat "$tmp/embed-configure.log"; fail "examples/embed does not configure"; }
"$cmake" --build "$tmp/embed" > "$tmp/embed-build.log" 2>&1 || { cat "$tmp/embed-build.log"; fail "examples/embed does not build"; }
"$tmp/embed/embed" "$scene" > "$tmp/embed.txt" || fail "examples/embed failed on $scene"
cat "$tmp/embed.txt"

# 3. The same forces from the installed command line, and its plot through the installed script.
"$prefix/bin/vascsim" -q experiment force-displacement "$scene" --out "$tmp/fd" > /dev/null 2> "$tmp/fd.log" \
  || fail "the installed vascsim experiment force-displacement failed"
[ -f "$tmp/fd/force_displacement.png" ] || fail "no force_displacement.png: the installed plot script did not run"
steps=$(grep -c '^step ' "$tmp/embed.txt")
[ "$steps" -ge 2 ] || fail "examples/embed printed $steps steps"
# force_displacement.csv: step, displacement_m, force_n, force_x_n, force_y_n, force_z_n (on the tool), ... (rows
# after step 0)
grep -v '^#' "$tmp/fd/force_displacement.csv" | awk -F, 'NR > 2 { print $1, $4, $5, $6 }' > "$tmp/cli-forces.txt"
awk '/^step / { split($0, a, "force on tool "); split(a[2], f, " "); sub(":", "", $2); print $2, f[2], f[3], f[4] }' \
  "$tmp/embed.txt" > "$tmp/embed-forces.txt"
[ "$(wc -l < "$tmp/cli-forces.txt")" -eq "$steps" ] || fail "the command line wrote $(wc -l < "$tmp/cli-forces.txt") steps, the example $steps"
# Same computation on one thread: equal to the printed digits; 1e-7 relative allows a last-digit rounding.
paste -d ' ' "$tmp/embed-forces.txt" "$tmp/cli-forces.txt" | awk '
  { for (i = 2; i <= 4; ++i) { d = $i - $(i + 4); if (d < 0) d = -d; s = ($i < 0 ? -$i : $i); if (d > 1e-7 * s + 1e-15) bad = 1 }
    if ($1 != $5) bad = 1; if ($4 + 0 == 0) zero = 1 }
  END { exit bad ? 1 : (zero ? 2 : 0) }' \
  || fail "the example's forces differ from the command line's (or are zero): $(paste -d ' ' "$tmp/embed-forces.txt" "$tmp/cli-forces.txt")"

# 4. The Python package from the prefix.
if [ "$python" != none ]; then
  pydir=$(ls -d "$prefix"/lib/python3*/dist-packages)
  PYTHONPATH=$pydir "$python" -c "
import vascsim, sys
assert vascsim.__file__.startswith('$prefix/'), vascsim.__file__
assert vascsim.__version__ == '$version', vascsim.__version__
assert vascsim.build_info()['bundled_files'] == '$prefix/share/vascsim', vascsim.build_info()['bundled_files']
print('python:', vascsim.__file__)" || fail "the installed Python package does not import from the prefix"
fi
echo "check_install: all checks passed ($prefix)"
