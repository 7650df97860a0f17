#!/usr/bin/python3
"""The paper's Fig. 10 from Python: a 6 Fr catheter tip presses the hand dorsal vein, and the force on it is drawn
against its travel.

The scene is quasi-static with frictionless contact. Run it as

    /usr/bin/python3 examples/python/fig10_force_displacement.py --coarse --out fig10.png

With an installed vascsim (the .deb, or `cmake --install` to a prefix on PYTHONPATH) it runs as is; from a
build tree, put the build's package first: PYTHONPATH=build/python. The experiment's files (summary.json,
force_displacement.csv) go to --data, by default a new temporary folder (printed at the end).

--coarse doubles the node spacing (0.3 mm instead of 0.15 mm) and halves the load steps (6 of 0.2 mm). Run on
2026-11-29 from the root of a build tree on 2 shared cores,

    PYTHONPATH=build/python /usr/bin/python3 examples/python/fig10_force_displacement.py --coarse --out fig10.png

it had 7,616 nodes and gave 2.158 mN at 0.2 mm and 10.003 mN at 1.2 mm in 94 s (56 s of CPU), with a warning
that the lattice under-resolves the contact up to 0.8 mm (VascsimWarning). The full scene's curve is in
docs/validation.md ("Catheter force-displacement").
"""

import argparse
import pathlib
import sys
import time

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import vascsim  # noqa: E402

# The coarse variant: 0.3 mm node spacing (the real-time scene's) and 6 load steps of 0.2 mm.
COARSE = {"geometry.node_spacing_m": 0.3e-3, "quasi_static.load_steps": 6}


def main():
    # The docstring's first paragraph, whole: its first line alone stops mid-sentence.
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0].replace("\n", " "))
    parser.add_argument("--coarse", action="store_true", help="0.3 mm node spacing, 6 load steps (fast)")
    parser.add_argument("--scene", default=vascsim.bundled_file("scenes/hand-dorsal-vein-catheter.json"),
                        help="the scene (default: the bundled scenes/hand-dorsal-vein-catheter.json)")
    parser.add_argument("--out", default="fig10.png", help="the picture (PNG)")
    parser.add_argument("--data", default=None,
                        help="folder for the experiment's files (default: a new temporary folder)")
    args = parser.parse_args()

    scene = vascsim.load_scene(args.scene, overrides=COARSE if args.coarse else None)
    start = time.monotonic()

    def progress(record, total):
        pressing_mn = record["tools"]["catheter"]["force_n"] * 1e3 + 0.0  # along the push; + 0.0: no "-0.000"
        print(f"step {record['step']}/{total}: force {pressing_mn:.3f} mN "
              f"({time.monotonic() - start:.0f} s)", file=sys.stderr)

    result = vascsim.force_displacement(scene, args.data, on_step=progress)
    u_mm, f_mn = result["displacement_m"] * 1e3, result["force_n"] * 1e3
    nodes = result["summary"]["nodes"]

    fig, ax = plt.subplots(figsize=(5, 3.6), dpi=150)
    ax.plot(u_mm, f_mn, "o-", label=f"{scene.model}, {nodes} nodes")
    ax.set_xlabel("catheter displacement (mm)")
    ax.set_ylabel("force on the catheter (mN)")
    ax.set_title("hand dorsal vein, 6 Fr catheter (Fig. 10)")
    ax.grid(True, alpha=0.3)
    ax.legend()
    fig.tight_layout()
    pathlib.Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(args.out)
    for u, f in zip(u_mm, f_mn):
        print(f"{u:.2f} mm  {f:.3f} mN")
    print(f"wrote {args.out} and {result['csv']} ({time.monotonic() - start:.0f} s)")


if __name__ == "__main__":
    main()
