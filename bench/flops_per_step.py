#!/usr/bin/env python3
"""The floating-point work of one rk4 step of a 3D scene, counted: runs `tether_bench
--benchmark_filter=EvaluationPart/rk4_step/SCENE` under callgrind with one count per instruction, disassembles the
binary (objdump) and sums, over the functions a step calls, its instructions and its floating-point operations (a
scalar add, subtract, multiply, divide or square root is one, a packed one two). docs/performance.md compares them
with the machine's floating-point bound. Needs valgrind and objdump (Debian: valgrind, binutils).

    python3 bench/flops_per_step.py [--build build] [--scene humanoid_file]
"""
import argparse
import collections
import os
import re
import shutil
import subprocess
import sys
import tempfile


def fail(message):
    """Bad input or a missing tool: the message and exit status 2."""
    print(f"flops_per_step.py: {message}", file=sys.stderr)
    sys.exit(2)

# the functions one rk4 step of a tree runs (TimeIntegrator::Advance and what it calls)
STEP_FUNCTIONS = ("TimeIntegrator<double>::Advance", "SettledStep<double", "ComputeAcceleration<double>",
                  "TreeAcceleration<double>", "AxisNormals<double>", "AccumulateForces<double>",
                  "EvaluateCoordinate<double>", "EvaluateCoordinateAt<double>", "JointCoordinates<double>::Find",
                  "UpdateFrames<double>", "Integrate<double>", "DexpInv<double>", "Elementwise<double")
SCALAR = {"addsd", "subsd", "mulsd", "divsd", "sqrtsd"}
PACKED = {"addpd", "subpd", "mulpd", "divpd", "sqrtpd"}


def position(token, last):
    """A callgrind position: absolute (0x...), relative (+n, -n) or the same (*)."""
    if token.startswith("0x"):
        return int(token, 16)
    if token[0] in "+-":
        return last + int(token)
    return last if token == "*" else int(token)


def step_costs(profile):
    """({instruction address: count} over STEP_FUNCTIONS, the number of steps) from a callgrind file."""
    names, costs = {}, collections.Counter()
    counting, callee, skip_next, last, steps = False, "", False, 0, 0
    with open(profile) as lines:
        for line in lines:
            named = re.match(r"^(c?)fn=\((\d+)\)(?: (.*))?$", line.rstrip("\n"))
            if named:
                caller_line, key, name = named.groups()
                if name:
                    names[key] = name
                if caller_line:
                    callee = names.get(key, "")
                else:
                    counting = any(f in names.get(key, "") for f in STEP_FUNCTIONS)
                continue
            if line.startswith("calls="):
                skip_next = True  # the next cost line is the call's inclusive cost
                if "TimeIntegrator<double>::Advance" in callee:
                    steps += int(line.split("=")[1].split()[0])
                continue
            if not line.strip() or not (line[0].isdigit() or line[0] in "+-*"):
                continue
            tokens = line.split()
            last = position(tokens[0], last)
            if skip_next:
                skip_next = False
            elif counting and len(tokens) >= 3:
                costs[last] += int(tokens[-1])
    return costs, steps


def mnemonics(binary):
    text = subprocess.run(["objdump", "-d", "--no-show-raw-insn", binary], capture_output=True, text=True,
                          check=True).stdout
    out = {}
    for line in text.splitlines():
        m = re.match(r"^\s*([0-9a-f]+):\s+(\S+)", line)
        if m:
            out[int(m.group(1), 16)] = m.group(2)
    return out


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--build", default="build", help="the build directory (default: build)")
    parser.add_argument("--scene", default="humanoid_file",
                        help="an EvaluationPart scene: humanoid_file, humanoid, hinge_chain10, hinge_chain200")
    args = parser.parse_args()
    for tool in ("valgrind", "objdump"):
        if shutil.which(tool) is None:
            fail(f"{tool} not found (Debian: apt install {tool if tool == 'valgrind' else 'binutils'})")
    binary = os.path.join(args.build, "bench", "tether_bench")
    if not os.path.isfile(binary):
        fail(f"{binary} not found (build the target tether_bench)")
    with tempfile.TemporaryDirectory() as scratch:
        profile = os.path.join(scratch, "callgrind.out")
        subprocess.run(["valgrind", "--tool=callgrind", "--dump-instr=yes", f"--callgrind-out-file={profile}", binary,
                        f"--benchmark_filter=EvaluationPart/rk4_step/{args.scene}$", "--benchmark_min_time=0.02"],
                       check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        costs, steps = step_costs(profile)
    if steps == 0:
        fail(f"--scene: no rk4 step of '{args.scene}' was run (see --help for the scenes)")
    kinds = mnemonics(binary)
    operations, instructions = collections.Counter(), sum(costs.values())
    for address, count in costs.items():
        kind = kinds.get(address)
        if kind in SCALAR or kind in PACKED:
            operations[kind] += count
    flops = sum(n * (2 if kind in PACKED else 1) for kind, n in operations.items())
    fp_instructions = sum(operations.values())
    multiplies = sum(n for kind, n in operations.items() if kind.startswith(("mul", "div", "sqrt")))
    adds = fp_instructions - multiplies
    print(f"{args.scene}, one rk4 step ({steps} steps counted):")
    print(f"  instructions            {instructions / steps:10.0f}")
    print(f"  floating-point ops      {flops / steps:10.0f}")
    print(f"  floating-point instrs   {fp_instructions / steps:10.0f}  (multiplies, divisions and roots "
          f"{multiplies / steps:.0f}, adds and subtractions {adds / steps:.0f})")
    for kind, n in operations.most_common():
        print(f"    {kind:7s} {n / steps:10.0f}")


if __name__ == "__main__":
    main()
