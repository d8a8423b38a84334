"""The committed ``generated/`` folder: NumPy and C for every built-in scene at its default size.

``python -m symgen.codegen.golden generated`` rewrites it; ``tests/test_generated_golden.py``
regenerates in memory and compares bytes (``pytest --update-golden`` rewrites instead).
"""
from __future__ import annotations

import sys

from ..io.builtin import get_scene, list_builtins
from ..model import derive
from .generate import generate, trace_all
from .targets import TARGETS
from ..io.writer import write_tree

README = """# generated/

Code emitted by `symgen generate` for every built-in scene at its default size, all functions,
one folder per scene and target (`<scene>/numpy/`, `<scene>/c/`), with `ops.json` beside each.
Do not edit: `tests/test_generated_golden.py` regenerates these files and compares bytes, and
`python -m symgen.codegen.golden generated` rewrites them.

In `c/`: `<scene>.h` and `<scene>.c` (C99, no allocation), `<scene>_ctypes.py` (binding that
compiles the source on first use, cached by content hash) and `test_<scene>.c` (standalone check
against symgen's dense reference model in 50-digit arithmetic:
`cc -std=c99 -O2 test_<scene>.c <scene>.c -lm && ./a.out`).
"""


def builtin_specs() -> list[str]:
    return [name + "".join(f":{k}={v}" for k, v in params.items()) for name, params, _ in list_builtins()]


def golden_files(specs=None) -> dict[str, str]:
    """Relative path -> text of everything under ``generated/``."""
    files = {"README.md": README}
    for spec in specs or builtin_specs():
        model = derive(get_scene(spec))
        lowered = trace_all(model)
        for target in TARGETS:
            gen = generate(model, target, lowered=lowered)
            for name, text in gen.files.items():
                files[f"{gen.module}/{gen.target}/{name}"] = text
    return files


def main(argv=None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    if len(argv) != 1:
        print("usage: python -m symgen.codegen.golden OUT_DIR", file=sys.stderr)
        return 2
    write_tree(argv[0], golden_files(), force=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
