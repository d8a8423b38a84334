"""Fuzzing the MJCF front door: mutated MJCF files (structural and numeric mutations of the files in
``tests/data/mjcf``) load and derive, or are refused with a :class:`~symgen.errors.SymgenError` --
never another exception, never a hang -- and a construct that changes MuJoCo's dynamics, put in a
body or a joint, is never accepted silently.

Shares the case bound, the hostile values and the generated-code checks of ``tests/fuzz_inputs.py``
(the YAML and URDF fuzzing of ``test_fuzz_front_door.py``). The CI share is a few dozen cases; the
``slow`` test runs a hundred, generating and compiling code for the accepted ones.
"""
from __future__ import annotations

import pathlib
import random
import re
import shutil

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from symgen.codegen.generate import generate, trace_all
from symgen.errors import SymgenError
from symgen.io.mjcf import parse_mjcf_text, scene_from_mjcf_model
from symgen.model import derive

from .fuzz_inputs import (CASE_BOUND, FUZZ_FUNCTIONS, HOSTILE_NUMBERS, INSERT_CHARS, _lines, _random_number,
                          _replace, check_generated, time_bound)

DATA = pathlib.Path(__file__).parent / "data" / "mjcf"
#: the files mutated, with weights (the loop models cost about a second each when accepted)
SEEDS = {"defaults_tree.xml": 6, "four_bar_sites.xml": 1, "five_bar.xml": 1}
CI = dict(deadline=None, database=None, derandomize=True,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture])
needs_cc = pytest.mark.skipif(shutil.which("cc") is None, reason="no C compiler")

_NUMBER = re.compile(r"(?<=[\" ])-?\d[\d.eE+-]*(?=[\" ])")
_VALUE = re.compile(r'(?<==")[^"]*(?=")')
_ELEMENT = re.compile(r"<(\w+)[^<>]*/>")
_START = re.compile(r"<(body|joint|default|worldbody|frame|inertial|site|option|compiler|equality|actuator)\b[^<>]*?"
                    r"(?=/?>)")
VALUES = HOSTILE_NUMBERS + ["", "  ", "0 0", "1 2 3 4", "nan 0 0", "inf", "0x10", "pi", "1/3", "1,2,3", "1e5 1e5 1e5",
                            "free", "ball", "slide", "hinge", "disable", "enable", "true", "false", "main", "slider",
                            "wrist", "nowhere", "world", "radian", "degree", "zyx", "xyzw", "auto", "é", "a b"]
#: elements a mutation puts in a body; those in DYNAMIC change MuJoCo's dynamics
INSERTS = ['<frame pos="0 0 0.1" euler="0 0 30"><body name="fz"><joint name="jfz"/>'
           '<inertial pos="0 0 0" mass="0.1" diaginertia="0.001 0.001 0.001"/></body></frame>',
           '<site name="sz" pos="0.1 0 0"/>', '<geom size="0.1"/>', '<camera/>', '<light/>', "<!-- c -->",
           "<![CDATA[x]]>", "&amp;", "&undefined;", '<joint name="extra"/>', '<body name="base"/>',
           '<inertial pos="0 0 0" mass="1" diaginertia="1 1 1"/>', '<body/>', '<frame childclass="nope"/>',
           '<freejoint/>']
DYNAMIC = ['<include file="more.xml"/>', '<replicate count="2"><body name="r"/></replicate>',
           '<attach model="m"/>', '<plugin plugin="p"/>', '<composite type="grid" count="2 2 1"/>',
           '<flexcomp name="f" type="grid" count="2 2 1"/>']
ATTRIBUTES = [' class="nope"', ' childclass="slider"', ' ref="30"', ' type="ball"', ' active="false"',
              ' mass="1e400"', ' pos="1e99999999 0 0"', ' euler="0 0 1/3"', ' quat="0 0 0 0"', ' axis="0 0 0"',
              ' damping="-1"', ' armature="1"', ' xyaxes="1 0 0 2 0 0"', ' zaxis="0 0 -1"', ' settotalmass="0"']
DYNAMIC_ATTRIBUTES = {"joint": [' type="ball" springdamper="0.1 1"'],
                      "body": [' gravcomp="1"', ' mocap="true"']}


def mutate_mjcf(rng: random.Random) -> tuple[str, bool]:
    """``(text, dynamic)``: a seed file with one to three mutations; ``dynamic`` when the last one
    put in a body or joint a construct that changes MuJoCo's dynamics (it must be refused; an
    earlier one may have been undone by a later mutation)."""
    names, weights = zip(*SEEDS.items())
    text = (DATA / rng.choices(names, weights)[0]).read_text(encoding="utf-8")
    for _ in range(rng.randint(1, 3)):
        dynamic = False                       # only the last mutation's insert is judged
        kind = rng.randrange(10)
        if kind == 0:
            text = _replace(rng, text, _NUMBER, HOSTILE_NUMBERS)
        elif kind == 1:
            text = _replace(rng, text, _NUMBER, [_random_number(rng, rng.choice((2, 40, 330)))])
        elif kind == 2:
            text = _replace(rng, text, _VALUE, VALUES + [" ".join(_random_number(rng, 3) for _ in range(3))])
        elif kind == 3:
            text = _replace(rng, text, _ELEMENT, [""])
        elif kind == 4 and text:
            text = _lines(rng, text)
        elif kind == 5:
            text, dynamic = _insert_element(rng, text)
        elif kind == 6:
            text, dynamic = _insert_attribute(rng, text)
        elif kind == 7:
            at = rng.randrange(len(text) + 1)
            text = text[:at] + rng.choice(INSERT_CHARS) + text[at:]
        elif kind == 8:
            text = text[: rng.randrange(len(text) + 1)]
        else:
            text = _sections(rng, text)
    return text, dynamic


def _insert_element(rng: random.Random, text: str) -> tuple[str, bool]:
    spots = [m.end() for m in re.finditer(r'<body name="[^"]*"[^<>/]*>', text)]
    if not spots:
        return text, False
    at, dynamic = rng.choice(spots), rng.random() < 0.4
    return text[:at] + rng.choice(DYNAMIC if dynamic else INSERTS) + text[at:], dynamic


def _insert_attribute(rng: random.Random, text: str) -> tuple[str, bool]:
    spots = [(m.end(), m.group(1)) for m in _START.finditer(text)]
    if not spots:
        return text, False
    at, tag = rng.choice(spots)
    dynamic = tag in DYNAMIC_ATTRIBUTES and rng.random() < 0.4
    return text[:at] + rng.choice(DYNAMIC_ATTRIBUTES[tag] if dynamic else ATTRIBUTES) + text[at:], dynamic


def _sections(rng: random.Random, text: str) -> str:
    """A second <option>, <compiler>, <default> or <worldbody> section, before or after the first."""
    section = rng.choice(['<option gravity="0 0 -1"><flag gravity="disable" damper="disable"/></option>',
                          '<compiler angle="radian" eulerseq="ZYX" settotalmass="3"/>',
                          '<default><joint damping="2" armature="0.5"/><default class="extra"/></default>',
                          '<worldbody><body name="second"><joint name="js" type="slide"/>'
                          '<inertial pos="0 0 0" mass="0.2" diaginertia="0.01 0.01 0.01"/></body></worldbody>',
                          '<equality><connect body1="nowhere" anchor="0 0 0"/></equality>',
                          '<actuator><motor joint="nowhere"/></actuator>', '<tendon/>', '<sensor/>'])
    start, end = text.find("<mujoco"), text.rfind("</mujoco>")
    at = text.find(">", start) + 1 if start >= 0 and rng.random() < 0.5 else (end if end >= 0 else len(text))
    return text[:at] + section + text[at:]


def run_mjcf_case(text: str, generate_code: bool = False) -> tuple[str, dict | None]:
    """``(outcome, files)`` of one text, as :func:`tests.fuzz_inputs.run_case` for YAML and URDF:
    the name of the SymgenError that refused it, or ``"accepted"`` (with the generated files when
    ``generate_code``). Any other exception propagates; the case is bounded by ``CASE_BOUND``."""
    with time_bound(CASE_BOUND):
        try:
            model = derive(scene_from_mjcf_model(parse_mjcf_text(text, "fuzz.xml")))
        except SymgenError as exc:
            return type(exc).__name__, None
        if not generate_code:
            return "accepted", None
        try:
            with np.errstate(all="ignore"):
                lowered = trace_all(model, list(FUZZ_FUNCTIONS))
                files = {t: generate(model, t, lowered=lowered) for t in ("numpy", "c")}
        except SymgenError as exc:
            return f"generator: {type(exc).__name__}", None
    return "accepted", {t: (g.module, g.files) for t, g in files.items()}


@settings(max_examples=25, **CI)
@given(rng=st.randoms(use_true_random=False))
def test_mutated_mjcf_is_accepted_whole_or_refused_typed(rng):
    text, dynamic = mutate_mjcf(rng)
    outcome, _ = run_mjcf_case(text)
    assert not (dynamic and outcome == "accepted"), f"a dynamics-changing construct was accepted:\n{text}"


@pytest.mark.slow
@needs_cc
@settings(max_examples=100, **CI)
@given(rng=st.randoms(use_true_random=False))
def test_thousands_of_mjcf_mutations_are_accepted_whole_or_refused_typed(rng, tmp_path_factory):
    text, dynamic = mutate_mjcf(rng)
    outcome, generated = run_mjcf_case(text, generate_code=rng.random() < 0.05)
    assert not (dynamic and outcome == "accepted"), f"a dynamics-changing construct was accepted:\n{text}"
    if generated is not None:
        check_generated(generated, tmp_path_factory.mktemp("fuzz_mjcf"))


def test_the_mutations_reach_acceptance_and_refusal():
    """The mutator is not vacuous: over a seeded batch, both outcomes occur, and so do dynamic
    inserts (each of them refused)."""
    rng = random.Random(7)
    outcomes, dynamic_refused = set(), 0
    for _ in range(25):
        text, dynamic = mutate_mjcf(rng)
        outcome, _ = run_mjcf_case(text)
        outcomes.add("accepted" if outcome == "accepted" else "refused")
        dynamic_refused += dynamic and outcome != "accepted"
    assert outcomes == {"accepted", "refused"} and dynamic_refused > 0
