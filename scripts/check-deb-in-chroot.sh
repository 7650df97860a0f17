#!/bin/sh
# Installs the vascsim Debian packages (`make package`) on a fresh Debian 12 (bookworm) in a chroot made by
# debootstrap, and checks there, with nothing else of this machine visible:
#   1. apt-get installs vascsim_*.deb with its Depends (and Recommends) from Debian's archive;
#   2. the installed `vascsim --version` reads /usr/share/vascsim, and `vascsim run` runs the default scene
#      (scenes/vein-indent.json, the scene of `make run`; a few minutes) and `vascsim experiment
#      force-displacement` draws its plot with the installed script;
#   3. `vascsim view` takes a headless picture (EGL on Mesa) of a bundled scene;
#   4. Debian's python3 imports the module and solves a bundled scene;
#   5. vascsim-dev_*.deb installs with its Depends and examples/embed builds against it and runs.
# Needs root, debootstrap (installed when missing) and network access to deb.debian.org; the chroot is about
# 1 GB. Not part of `make test` (docs/api.md, "Debian package").
# Usage: scripts/check-deb-in-chroot.sh [PACKAGE_DIR (build-package)] [CHROOT_DIR (/var/tmp/vascsim-deb-chroot)]
set -eu
src=$(cd "$(dirname "$0")/.." && pwd)
pkgdir=$(cd "${1:-build-package}" && pwd)
root=${2:-/var/tmp/vascsim-deb-chroot}
mirror=http://deb.debian.org/debian

runtime=$(ls "$pkgdir"/vascsim_*.deb | tail -n 1)
dev=$(ls "$pkgdir"/vascsim-dev_*.deb | tail -n 1)
[ -f "$runtime" ] && [ -f "$dev" ] || { echo "no vascsim_*.deb and vascsim-dev_*.deb in $pkgdir (make package)" >&2; exit 2; }

command -v debootstrap > /dev/null || DEBIAN_FRONTEND=noninteractive apt-get install -y debootstrap
if [ ! -x "$root/usr/bin/apt-get" ]; then
  echo "== debootstrap bookworm into $root"
  debootstrap bookworm "$root" "$mirror"
fi
mount -t proc proc "$root/proc"
trap 'umount "$root/proc"' EXIT
in_root() { chroot "$root" /usr/bin/env -i HOME=/root PATH=/usr/sbin:/usr/bin:/sbin:/bin DEBIAN_FRONTEND=noninteractive "$@"; }

rm -rf "$root/tmp/vascsim-check" && mkdir -p "$root/tmp/vascsim-check"
cp "$runtime" "$dev" "$root/tmp/vascsim-check/"
cp -r "$src/examples/embed" "$root/tmp/vascsim-check/embed"

echo "== 1. apt-get install $(basename "$runtime")"
in_root apt-get update -q
in_root apt-get install -y "/tmp/vascsim-check/$(basename "$runtime")"
in_root dpkg -s vascsim | sed -n 's/^\(Version\|Depends\|Recommends\):/  &/p'

echo "== 2. the installed command"
in_root vascsim --version
in_root sh -c 'cd /tmp/vascsim-check && start=$(date +%s) && vascsim run /usr/share/vascsim/scenes/vein-indent.json \
  --out out/vein-indent && echo "default scene: $(( $(date +%s) - start )) s"'
in_root sh -c 'cd /tmp/vascsim-check && vascsim -q experiment force-displacement /usr/share/vascsim/scenes/hand-dorsal-vein-catheter.json \
  --set geometry.node_spacing_m=0.3e-3 --out out/fd && ls -l out/fd/force_displacement.png'

echo "== 3. a headless picture"
in_root sh -c 'cd /tmp/vascsim-check && vascsim -q view /usr/share/vascsim/scenes/realtime/hand-dorsal-vein-catheter.json \
  --frames 2 --size 320x240 --screenshot out/view.png && ls -l out/view.png'

echo "== 4. the Python module"
in_root python3 -c '
import vascsim
scene = vascsim.load_scene(vascsim.bundled_file("scenes/hand-dorsal-vein-catheter.json"),
                           overrides={"geometry.node_spacing_m": 0.3e-3, "quasi_static.load_steps": 2})
sim = vascsim.Simulation(scene)
records = sim.solve()
print(vascsim.__file__, vascsim.__version__, sim.num_nodes, "nodes; force on the catheter",
      records[-1]["tools"]["catheter"]["force_n"], "N")'

echo "== 5. vascsim-dev and examples/embed"
in_root apt-get install -y cmake g++ make "/tmp/vascsim-check/$(basename "$dev")"
in_root sh -c 'cd /tmp/vascsim-check && cmake -S embed -B embed-build -DCMAKE_BUILD_TYPE=Release > /dev/null \
  && cmake --build embed-build && embed-build/embed /usr/share/vascsim/scenes/vein-indent.json quasi_static.load_steps=2'
echo "check-deb-in-chroot: all checks passed ($root)"
