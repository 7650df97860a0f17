#!/usr/bin/env python3
"""The real-time benchmark's bundled references (data/benchmarks/reference-<scene>.csv) are the ones it would compute.

scripts/realtime_benchmark.py takes a scene's bundled reference instead of computing it (8-26 minutes) when the
file's key line matches the reference scene's SHA-256, the press-and-slide path and the step. This check fails when
a reference scene or a path in the script's CASES changes and the bundled file was not computed again
(`--fresh-reference --bundle-reference`), when a bundled file has no key or no rows, and when the reader takes a
file whose key differs from the one asked for (a key with another step is built and must be refused).

    /usr/bin/python3 tests/python/check_bundled_references.py
"""
import pathlib
import sys
import tempfile

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "scripts"))
import realtime_benchmark as rb  # noqa: E402


def main():
    failures = []
    bundled = sorted((ROOT / "data" / "benchmarks").glob("reference-*.csv"))
    if not bundled:
        failures.append("no bundled reference in data/benchmarks")
    known = {rb.bundled_reference_file(scene): (scene, case) for scene, case in rb.CASES.items()}
    for file in bundled:
        if file not in known:
            failures.append(f"{file.name}: no scene of the script's CASES bundles this file")
            continue
        scene, case = known[file]
        key = rb.reference_key(case, case["reference_step"])
        found = rb.read_reference(file, key)
        if found is None:
            failures.append(f"{file.name}: its key is not that of {scene} today (recompute it: "
                            f"scripts/realtime_benchmark.py --scene {scene} --fresh-reference --bundle-reference)")
            continue
        ls, fs = found
        if len(ls) < 10 or any(b <= a for a, b in zip(ls, ls[1:])):
            failures.append(f"{file.name}: {len(ls)} poses, not increasing along the path")
        if max(fs) <= 0.0:
            failures.append(f"{file.name}: no force along the path")
        # A key for another step must be refused.
        other = dict(key, reference_step_m=key["reference_step_m"] * 2)
        if rb.read_reference(file, other) is not None:
            failures.append(f"{file.name}: read for a key with another step")
        with tempfile.TemporaryDirectory() as tmp:
            copy = pathlib.Path(tmp) / "reference.csv"
            copy.write_text("".join(line for line in file.read_text().splitlines(keepends=True)
                                    if not line.startswith("# key: ")))
            if rb.read_reference(copy, key) is not None:
                failures.append(f"{file.name}: a copy without its key line was taken")
            if rb.read_reference(copy) != found:
                failures.append(f"{file.name}: read without a key, the rows differ")
        print(f"{file.name}: {len(ls)} poses, force up to {max(fs) * 1e3:.3f} mN, key of {scene}")
    for f in failures:
        print("FAIL:", f, file=sys.stderr)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
