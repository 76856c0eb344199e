#!/usr/bin/env python3
"""docs/contract.md against the contract the acceptance checks hold tether to: from the first section on, the two
must say the same (the repository keeps its own copy so that the code's references to it resolve in a clone)."""
import sys
from pathlib import Path


def body(path):
    text = Path(path).read_text(encoding="utf-8")
    start = text.find("\n## ")
    if start < 0:
        sys.exit(f"{path}: no section found")
    return text[start:]


ours, theirs = sys.argv[1], sys.argv[2]
if body(ours) != body(theirs):
    sys.exit(f"{ours} differs from {theirs} after its preamble: copy the sections over")
print(f"{ours} says what {theirs} says")
