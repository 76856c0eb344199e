#!/usr/bin/env python3
"""Runs the public acceptance checks' gradient cases (check.py's `gradient` section and `rigid3d`'s gradient check)
with the discrete adjoint in place of the Jets:

    python3 tests/acceptance/adjoint_gradients.py PATH/TO/check.py --tether build/tether

Wherever a check asks `tether gradient ... --method jet`, this runs `--method adjoint` as well, requires the two to
agree to 1e-8 (relative to max(|g|, 1e-3 of the largest component), as tests/gradient_test.cc) and hands the
adjoint's result to the check, which then holds it to its own reference: the loss re-derived from `simulate`, and
central differences (`--method fd`) to 1e-5. Prints check.py's summary line; exit status 1 if any case fails.
"""
import importlib.util
import os
import shutil
import sys
import tempfile

AGREEMENT = 1e-8


def load(path):
    sys.path.insert(0, os.path.dirname(os.path.abspath(path)))
    spec = importlib.util.spec_from_file_location("check", path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # check.py hands itself, by name, to its rigid3d part
    spec.loader.exec_module(module)
    return module


def main(argv):
    if len(argv) != 3 or argv[1] != "--tether":
        sys.exit(__doc__)
    check = load(argv[0])

    class AdjointCtx(check.Ctx):
        def json_cmd(self, *args, **kwargs):
            args = [str(a) for a in args]
            if args[0] != "gradient" or args[-2:] != ["--method", "jet"]:
                return super().json_cmd(*args, **kwargs)
            jet, _ = super().json_cmd(*args, **kwargs)
            adjoint, seconds = super().json_cmd(*args[:-1], "adjoint", **kwargs)
            if adjoint["method"] != "adjoint":
                raise check.Failure(f"--method adjoint reported method {adjoint['method']!r}")
            scale = max(abs(g) for g in jet["gradient"].values())
            for pointer, g in jet["gradient"].items():
                a = adjoint["gradient"][pointer]
                if abs(a - g) > AGREEMENT * max(abs(g), 1e-3 * scale):
                    raise check.Failure(f"d loss / d {pointer}: adjoint {a:.15g} vs jet {g:.15g}")
            if abs(adjoint["loss"] - jet["loss"]) > 1e-12 * abs(jet["loss"]):
                raise check.Failure(f"loss: adjoint {adjoint['loss']!r} vs jet {jet['loss']!r}")
            return adjoint, seconds

    work = tempfile.mkdtemp(prefix="tether-adjoint-acceptance-")
    ctx = AdjointCtx(os.path.abspath(argv[2]), work)
    cases = [("gradient", name, fn) for name, fn in check.SECTIONS["gradient"]]
    cases += [("rigid3d", name, fn) for name, fn in check.SECTIONS["rigid3d"] if name == "gradient"]
    for section, name, fn in cases:
        check.check(section, name, fn, ctx)
    shutil.rmtree(work, ignore_errors=True)
    bad = sum(1 for r in check.RESULTS if not r[2])
    print(f"{len(check.RESULTS) - bad} passed, {bad} failed")
    return 1 if bad or not check.RESULTS else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
