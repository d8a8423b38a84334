"""Mutated scene files and URDFs, and what must hold for each: shared by the fuzz test (a few
hundred cases, driven by hypothesis) and ``benchmarks/fuzz_front_door.py`` (thousands, seeded).

A mutator takes a :class:`random.Random` (hypothesis' ``st.randoms()`` in the suite, so failures
shrink; a seeded one in the benchmark) and returns the mutated text. :func:`run_case` loads,
derives and generates code for one text under a time bound and returns its outcome; only a
:class:`~symgen.errors.SymgenError` may escape the front door. :func:`check_generated` compiles
the C with the strict flags and imports the Python files.
"""
from __future__ import annotations

import hashlib
import importlib.util
import pathlib
import random
import re
import signal
import subprocess
import sys
from contextlib import contextmanager

import numpy as np

from symgen.codegen.generate import generate, trace_all
from symgen.errors import SymgenError
from symgen.model import derive
from symgen.io.scene_yaml import load_scene
from symgen.io.urdf import scene_from_urdf

ROOT = pathlib.Path(__file__).resolve().parents[1]
#: no case may take longer than this (seconds) to load, derive and generate
CASE_BOUND = 30.0
#: the functions generated for each accepted scene (the others are built from the same recursions)
FUZZ_FUNCTIONS = ("inverse_dynamics", "forward_dynamics")
STRICT = ["-std=c99", "-Wall", "-Wextra", "-Werror", "-pedantic"]

PENDULUM = """\
name: pendulum
description: a double pendulum
gravity: [0, 0, -9.81]
parameters: {m_upper: 1.0}
bodies:
  upper: {mass: m_upper, com: [0.5, 0, 0], inertia: [0.01, 0.1, 0.1]}
  lower: {mass: 1.0, com: [0.5, 0, 0], inertia: [0.01, 0.1, 0.1, 0, 0, 0.001]}
joints:
  shoulder: {type: revolute, parent: world, child: upper, axis: y, actuated: true, q0: pi/6,
             friction: {viscous: 0.1, coulomb: 0}}
  elbow: {type: revolute, parent: upper, child: lower, xyz: [1, 0, 0], rpy: [0, 0, 0.5], axis: y,
          actuated: true, rotor_inertia: 0.01}
frames:
  tip: {body: lower, xyz: [1, 0, 0], quat: [1, 0, 0, 0]}
motion: {joints: [shoulder, elbow]}
"""

URDF = """<?xml version="1.0"?>
<robot name="arm">
  <link name="base"/>
  <link name="upper">
    <inertial><origin xyz="0 0 0.2" rpy="0 0 0"/><mass value="2.0"/>
      <inertia ixx="0.03" ixy="0" ixz="0" iyy="0.03" iyz="0" izz="0.004"/></inertial>
  </link>
  <link name="lower">
    <inertial><origin xyz="0 0 0.15"/><mass value="1.0"/>
      <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.001"/></inertial>
  </link>
  <link name="tool"/>
  <joint name="shoulder" type="revolute">
    <parent link="base"/><child link="upper"/><origin xyz="0 0 0.1" rpy="0 0 0"/>
    <axis xyz="0 1 0"/><limit lower="-3" upper="3" effort="10" velocity="2"/>
    <dynamics damping="0.1" friction="0"/>
  </joint>
  <joint name="elbow" type="continuous">
    <parent link="upper"/><child link="lower"/><origin xyz="0 0 0.4" rpy="0 1.5707963267948966 0"/>
    <axis xyz="0 1 0"/>
  </joint>
  <joint name="flange" type="fixed">
    <parent link="lower"/><child link="tool"/><origin xyz="0 0 0.3"/>
  </joint>
</robot>
"""


def yaml_seeds() -> list[str]:
    """Scene texts the YAML mutations start from: a double pendulum and built-in scenes."""
    scenes = ROOT / "symgen" / "io" / "scenes"
    return [PENDULUM] + [(scenes / f"{name}.yaml").read_text(encoding="utf-8")
                         for name in ("four_bar", "five_bar", "arm_on_plane")]


HOSTILE_NUMBERS = ["1e99999999", "-1e-999999", "1e308", "1e-320", "1e160", "1e300", "-1e31", "1e-31", "0.0",
                   "-0", "1/0", "'1/0'", ".nan", ".inf", "-.inf", "0x7fffffff", "0o777", "190:20:30", "1_000.5",
                   "'3*pi/0'", "'-pi/2'", "'1e9999*pi'", "9" * 5000, "7" * 200, "'" + "1" * 999 + "'",
                   "1e29", "-1e-29", "123456789012345678901234567890", "'1/3'", "true", "null", "~", "[]", "{}",
                   "[1, 2]", "'m_upper'", "'unknown_param'", "1e-7", "'  2.5e-3 '", "+.5", "5.", "'.'"]
HOSTILE_TEXT = ['"nul \\0 byte"', '"lone \\ud800 surrogate"', '"bidi \\u202e override"', '"ends in backslash \\\\"',
                '"trigraph ??/"', "'*/ /* //'", '"line\\u2028break"', '"tab\\tand\\x7f"', "'\"\"\" quotes'",
                "math", "numpy", "class", "ctypes", "os", "stdio", "symgen", "world", "pi", "'white space'",
                "x" * 70, "!!python/object:os.system", "!!binary aGVsbG8=", "&anchor 1", "*undefined", "<<: {}",
                "é_unicode", "'\\u00e9'", "A" * 3]
INSERT_CHARS = ["\x00", "\x01", "\x1b", "\x7f", "\ud800", "\u202e", "\t", "\r", "\n", "\\", "[", "{", "&", "*", "!",
                ":", "-", "'", '"', "#", "%", "@", "`", "|", ">", "é", "\ufeff"]
_NUMBER = re.compile(r"(?<![\w.])-?\d[\w./+-]*")
_SCALAR = re.compile(r"(?<=[:,\[{] )[A-Za-z_][\w]*")


def _replace(rng: random.Random, text: str, pattern: re.Pattern, choices: list[str]) -> str:
    spans = [m.span() for m in pattern.finditer(text)]
    if not spans:
        return text
    start, end = rng.choice(spans)
    return text[:start] + rng.choice(choices) + text[end:]


def _lines(rng: random.Random, text: str) -> str:
    lines = text.splitlines(keepends=True)
    i, j = rng.randrange(len(lines)), rng.randrange(len(lines))
    op = rng.choice(("delete", "duplicate", "swap"))
    if op == "delete":
        del lines[i]
    elif op == "duplicate":
        lines.insert(j, lines[i])
    else:
        lines[i], lines[j] = lines[j], lines[i]
    return "".join(lines)


def _random_number(rng: random.Random, exponents: int = 330) -> str:
    return f"{rng.choice(('', '-'))}{rng.random():.{rng.randint(1, 25)}g}e{rng.randint(-exponents, exponents)}"


def _deep(rng: random.Random, text: str) -> str:
    depth = rng.choice((3, 20, 31, 33, 200, 1000, 3000))
    open_, close = rng.choice((("[", "]"), ("{a: ", "}")))
    return _replace(rng, text, _NUMBER, [open_ * depth + "1" + close * depth])


def _alias_bomb(rng: random.Random, text: str) -> str:
    width, levels = rng.randint(2, 12), rng.randint(1, 9)
    defs = [f"  l0: &l0 [{', '.join(['1'] * width)}]"]
    defs += [f"  l{i}: &l{i} [{', '.join([f'*l{i - 1}'] * width)}]" for i in range(1, levels)]
    anchors = "x_anchors:\n" + "\n".join(defs) + "\n"
    target = rng.choice(("gravity", "xyz", "com"))
    body = re.sub(rf"{target}: \[[^\]]*\]", f"{target}: *l{levels - 1}", text, count=1)
    return anchors + body


def _yaml_mutation(rng: random.Random, text: str) -> str:
    kind = rng.randrange(12)
    if kind == 11:    # a plausible edit: the scene usually stays valid, so code is generated
        return _replace(rng, text, _NUMBER, [_random_number(rng, 2)])
    if kind == 0:
        return _replace(rng, text, _NUMBER, HOSTILE_NUMBERS)
    if kind == 1:
        return _replace(rng, text, _NUMBER, [_random_number(rng)])
    if kind == 2:
        return _replace(rng, text, _SCALAR, HOSTILE_TEXT)
    if kind == 3:
        return _lines(rng, text)
    if kind == 4:
        return _deep(rng, text)
    if kind == 5:
        return _alias_bomb(rng, text)
    if kind == 6:
        spots = [m.start() for m in re.finditer(r" actuated: true,?", text)]
        if spots:
            at = rng.choice(spots)
            return text[:at] + re.sub(r"^ actuated: true,?", "", text[at:], count=1)
        return text
    if kind == 7:
        line = rng.choice((f"description: {rng.choice(HOSTILE_TEXT)}\n", f"name: {rng.choice(HOSTILE_TEXT)}\n"))
        key = line.split(":")[0]
        return re.sub(rf"(?m)^{key}:.*\n", "", text) + line
    if kind == 8:
        at = rng.randrange(len(text) + 1)
        return text[:at] + rng.choice(INSERT_CHARS) + text[at:]
    if kind == 9:
        return text[: rng.randrange(len(text) + 1)]
    return re.sub(r"constraint_forces: \w+", f"constraint_forces: {rng.choice(('joint', 'operational', 'x'))}", text)


def mutate_yaml(rng: random.Random) -> str:
    """A seed scene with one to three mutations."""
    text = rng.choice(yaml_seeds())
    for _ in range(rng.randint(1, 3)):
        text = _yaml_mutation(rng, text)
    return text


_ATTRIBUTE = re.compile(r'(?<==")[^"]*(?=")')
_ELEMENT = re.compile(r"<(\w+)[^<>]*/>|<(\w+)[^<>]*>[^<>]*</\2>")
URDF_INSERTS = ["<visual><geometry/></visual>", "<visual/>", "<visual><geometry><box/></geometry></visual>",
                "<collision><geometry><mesh/></geometry></collision>", "<visual><material/></visual>",
                '<mimic joint="nowhere"/>', '<origin xyz="1 2"/>', "<inertial/>", '<inertial><mass value="1"/></inertial>',
                "<limit/>", '<axis xyz="0 0 0"/>', "<calibration/>", "<safety_controller/>", "<!-- c -->",
                "<![CDATA[x]]>", "&amp;", "&undefined;", '<joint name="j"/>', '<link name="upper"/>']
URDF_VALUES = HOSTILE_NUMBERS + ["0 0", "1 2 3 4", "nan nan nan", "inf 0 0", "", "   ", "floating", "planar",
                                 "screw", "base", "nowhere", "upper", "1e5 1e5 1e5"]


def _urdf_mutation(rng: random.Random, text: str) -> str:
    kind = rng.randrange(7)
    if kind == 0:
        return _replace(rng, text, _ATTRIBUTE, URDF_VALUES + [_random_number(rng)])
    if kind == 1:
        return _replace(rng, text, _ATTRIBUTE, [" ".join(_random_number(rng) for _ in range(3))])
    if kind == 2:
        return _replace(rng, text, _ELEMENT, [""])
    if kind == 3:
        spots = [m.end() for m in re.finditer(r"<(link|joint|inertial|visual)[^<>/]*>", text)]
        if spots:
            at = rng.choice(spots)
            return text[:at] + rng.choice(URDF_INSERTS) + text[at:]
        return text
    if kind == 4:
        at = rng.randrange(len(text) + 1)
        return text[:at] + rng.choice(INSERT_CHARS) + text[at:]
    if kind == 5:
        return text[: rng.randrange(len(text) + 1)]
    return _lines(rng, text)


def mutate_urdf(rng: random.Random) -> str:
    text = URDF
    for _ in range(rng.randint(1, 3)):
        text = _urdf_mutation(rng, text)
    return text


# ---------------------------------------------------------------------------- one case
class CaseTimeout(Exception):
    """A case ran longer than :data:`CASE_BOUND`."""


@contextmanager
def time_bound(seconds: float):
    """Raise :class:`CaseTimeout` in the main thread after ``seconds`` (a hard bound on hangs)."""
    def expire(signum, frame):
        raise CaseTimeout(f"longer than {seconds} s")

    old = signal.signal(signal.SIGALRM, expire)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, old)


def run_case(kind: str, text: str) -> tuple[str, dict | None]:
    """``(outcome, files)``: the name of the SymgenError that refused the text (``"generator:
    ..."`` when the code generator refused a derived model), or ``"accepted"`` with the generated
    files ``{target: (module, {name: text})}``. Any other exception propagates."""
    with time_bound(CASE_BOUND):
        try:
            scene = load_scene(text) if kind == "yaml" else scene_from_urdf(text)
            model = derive(scene)
        except SymgenError as exc:
            return type(exc).__name__, None
        try:
            with np.errstate(all="ignore"):
                lowered = trace_all(model, list(FUZZ_FUNCTIONS))
                files = {t: generate(model, t, lowered=lowered) for t in ("numpy", "c")}
        except SymgenError as exc:   # a documented refusal of the code generator, typed
            return f"generator: {type(exc).__name__}", None
    return "accepted", {t: (g.module, g.files) for t, g in files.items()}


def check_generated(generated: dict, folder: pathlib.Path, compiled: set | None = None) -> None:
    """Write the files, compile the C with :data:`STRICT` flags (skipped for a source already in
    ``compiled``, a set of digests) and import the NumPy module and the ctypes binding."""
    for target, (module, files) in generated.items():
        digest = hashlib.sha256(repr(sorted(files.items())).encode("utf-8", "surrogatepass")).hexdigest()[:16]
        out = folder / f"{module}-{target}-{digest}"
        out.mkdir(parents=True, exist_ok=True)
        for name, text in files.items():
            (out / name).write_text(text, encoding="utf-8")
        if target == "c":
            if compiled is None or digest not in compiled:
                result = subprocess.run(["cc", *STRICT, "-O0", "-c", f"{module}.c", f"test_{module}.c"],
                                        cwd=out, capture_output=True, text=True)
                assert result.returncode == 0, f"generated C does not compile:\n{result.stderr[:2000]}"
                if compiled is not None:
                    compiled.add(digest)
            _import(out / f"{module}_ctypes.py", f"fuzz_c_{digest}")
        else:
            _import(out / f"{module}.py", f"fuzz_np_{digest}")


def _import(path: pathlib.Path, name: str) -> None:
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    sys.modules.pop(name, None)
