"""Seeded mutations of ``symgen`` command lines, run in-process through :func:`symgen.cli.main`.

Each case starts from one of :data:`TEMPLATES` -- a valid command line of every command on a small
scene, its work bounded by its options (a short ``--t-end``, few states, a small budget) -- and
applies one to three mutations drawn by ``random.Random(seed)``: an option's value replaced by a
hostile token (:data:`HOSTILE`), the scene replaced by a bad spec or file, a token dropped or
duplicated, an option of another command inserted, a number scaled. The options that set the
amount of work (:data:`WORK_OPTIONS`) only shrink or turn invalid, so that every case is bounded. The case runs
under :func:`~fuzz_inputs.time_bound` in a scratch working directory with stdout and stderr
captured. An acceptable outcome is: the parser refusing the line (status 2, no traceback), or the
command returning 0, 1 or 2 -- status 2 with one line ``symgen: error: ...`` on stderr. Anything
else is a finding: an exception escaping ``main``, a traceback on stderr, a status-2 message that
is not one line, or a case longer than :data:`CLI_CASE_BOUND` (a hang).
"""
from __future__ import annotations

import contextlib
import io
import os
import pathlib
import random
import warnings

from .fuzz_inputs import CaseTimeout, time_bound

#: seconds a case may take before it counts as a hang
CLI_CASE_BOUND = 30.0
#: small scenes the templates run on (each command's work stays under a second or so)
SCENES = ("chain:n=2", "four_bar", "five_bar", "chain:n=1")
DATA = pathlib.Path(__file__).resolve().parent / "data"

#: valid command lines; ``{S}`` a scene of :data:`SCENES`, ``{OUT}`` a fresh folder name,
#: ``{CSV}`` a data file of the case's scene (written by the fixture), ``{URDF}`` a URDF file
TEMPLATES: tuple[tuple[str, ...], ...] = (
    ("scenes",), ("scenes", "--json"),
    ("info", "{S}"), ("info", "{S}", "--json"),
    ("steps", "{S}", "-q", "M"), ("steps", "{S}", "--field", "float", "-q", "T_S", "-q", "J_f"),
    ("export", "{S}"),
    ("prove", "{S}", "--points", "1", "--seed", "0", "--method", "exact", "--json"),
    ("generate", "{S}", "--target", "numpy", "--out", "{OUT}", "--functions", "mass_matrix"),
    ("generate", "{S}", "--target", "c", "--out", "{OUT}", "--functions", "gravity", "--force"),
    ("generate", "{S}", "--target", "numpy", "--out", "{OUT}", "--functions", "control", "--uncertain", "all",
     "--gain", "2"),
    ("ops", "{S}", "--functions", "mass_matrix", "--json"),
    ("simulate", "{S}", "--t-end", "0.02", "--backend", "numpy", "--method", "rk4", "--step", "0.01"),
    ("simulate", "{S}", "--t-end", "0.02", "--backend", "numpy", "--method", "RK45", "--rtol", "1e-6",
     "--atol", "1e-8", "--speed", "0.1", "--json"),
    ("accuracy", "{S}", "--states", "1", "--dps", "25", "--functions", "mass_matrix", "--lambdify-timeout", "0",
     "--json"),
    ("stability", "--list"),
    ("stability", "--cases", "length_1e+03", "--no-integrators", "--backend", "numpy", "--json"),
    ("check", "{URDF}", "--against", "pinocchio", "--states", "1", "--json"),
    ("control", "{S}", "--t-end", "0.02", "--json"),
    ("params", "{S}", "--states", "20", "--seed", "1", "--json"),
    ("excite", "{S}", "--harmonics", "1", "--samples", "8", "--max-evals", "2", "--budget", "2", "--json"),
    ("identify", "chain:n=2", "{CSV}", "--weights", "residual", "--json"),
)

#: hostile values for an option or a positional argument
HOSTILE: tuple[str, ...] = (
    "0", "-1", "1", "2", "-0", "0.5", "nan", "inf", "-inf", "1e309", "1e-320", "", " ", "abc", "1e3", "1e6",
    "999999999", "0x10", "1_000", "a,b", ",", ",,", "mass_matrix,", "all", "none", "input", "*", "?", "-", "--",
    "--json", "../x", "/dev/null", "/", "/nonexistent/f.csv", "é", "\u2028", "x" * 300, "1,2,3", "1e-3,nan",
    "{EMPTY}", "{DIR}", "{BINARY}", "{BADCSV}", "{BADYAML}", "{CSV}", "{URDF}",
)
#: bad scene specs and files
BAD_SCENES: tuple[str, ...] = (
    "chain:n=0", "chain:n=201", "chain:n=-3", "chain:n=2.5", "chain:m=2", "chain:n=", "chain:", ":n=2", "nope",
    "multi_arm:h=17", "four_bar:x=1", "FOUR_BAR", "four_bar ", "{EMPTY}", "{DIR}", "{BINARY}", "{BADYAML}",
    "{CSV}", "/nonexistent/scene.yaml", str(DATA / "urdf" / "malformed.urdf"), str(DATA / "urdf" / "cycle.urdf"),
    str(DATA / "mjcf" / "defaults_tree.xml"),
)
#: options of every command, inserted into lines of other commands
FOREIGN = ("--t-end", "--states", "--dps", "--points", "--functions", "--target", "--out", "--budget", "--cases",
           "--report", "--data", "--weights", "--gain", "--uncertain", "--quantity", "--field", "--fit",
           "--method", "--step", "--v0", "--bogus", "-q", "--json", "--force", "--consistent", "--list")
#: options whose value sets how much work a command does: the templates give them small values, and
#: a mutation replaces those only by values that are invalid or smaller (:data:`SHRINKING`) -- a
#: larger but valid value is a long run the user asked for, not a hang (their upper bounds are the
#: parser's, tested in ``tests/test_cli_hardening.py``)
WORK_OPTIONS = frozenset({"--t-end", "--step", "--states", "--dps", "--points", "--budget", "--max-evals",
                          "--samples", "--harmonics", "--cases", "--functions", "--data-samples", "--rtol", "--atol",
                          "--lambdify-timeout", "--list", "--no-integrators"})
SHRINKING = ("0", "-1", "-0", "nan", "inf", "-inf", "1e309", "", "abc", "1e-320", " ", "1e-300", "-1e-9")


def _fill(token: str, rng: random.Random, files: dict[str, str], counter: list[int]) -> str:
    if token == "{S}":
        return rng.choice(SCENES)
    if token == "{OUT}":
        counter[0] += 1
        return f"out{counter[0]}"
    for key, path in files.items():
        token = token.replace("{" + key + "}", path)
    return token


def _hostile(option: str | None, rng: random.Random, files: dict[str, str], counter: list[int]) -> str:
    pool = SHRINKING if option in WORK_OPTIONS else HOSTILE
    return _fill(rng.choice(pool), rng, files, counter)


def mutate_argv(rng: random.Random, files: dict[str, str]) -> list[str]:
    """One mutated command line (see the module docstring). The template's flags of
    :data:`WORK_OPTIONS` and their values are never dropped; those values change only to
    :data:`SHRINKING` ones or by a factor 0, -1 or 1e-9."""
    counter = [0]
    argv = [_fill(t, rng, files, counter) for t in rng.choice(TEMPLATES)]
    kept = [t in WORK_OPTIONS or (i > 0 and argv[i - 1] in WORK_OPTIONS) for i, t in enumerate(argv)]
    for _ in range(rng.randint(1, 3)):
        kind = rng.randrange(6)
        spots = list(range(1, len(argv)))
        free = [i for i in spots if not kept[i]]
        if kind == 0 and spots:                         # a value replaced
            i = rng.choice(spots)
            argv[i] = _fill(rng.choice(SHRINKING if kept[i] else HOSTILE), rng, files, counter)
        elif kind == 1 and len(argv) > 1 and not argv[1].startswith("-"):    # the scene replaced
            argv[1] = _fill(rng.choice(BAD_SCENES), rng, files, counter)
        elif kind == 2 and free:                        # a token dropped (never a work bound)
            i = rng.choice(free)
            del argv[i], kept[i]
        elif kind == 3 and spots:                       # a token (and the next) duplicated
            i = rng.choice(spots)
            argv[i:i], kept[i:i] = argv[i:i + 2], kept[i:i + 2]
        elif kind == 4:                                 # an option of another command
            i = rng.randint(1, len(argv))
            option = rng.choice(FOREIGN)
            added = [option, _hostile(option, rng, files, counter)][:rng.randint(1, 2)]
            argv[i:i], kept[i:i] = added, [False] * len(added)
        else:                                           # a number scaled
            numeric = [i for i in spots if _is_number(argv[i])]
            if numeric:
                i = rng.choice(numeric)
                factors = (-1.0, 0.0, 1e-9) if kept[i] else (-1.0, 0.0, 10.0, 1e3, 1e-9)
                argv[i] = repr(float(argv[i]) * rng.choice(factors))
    return argv


def _is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def make_files(folder: pathlib.Path) -> dict[str, str]:
    """The files the placeholders name: an empty file, a folder, a binary file, a CSV that is not
    data, a YAML that is not a scene, a valid identification CSV (``chain:n=2``), a URDF."""
    import symgen
    from symgen.identification.data import simulated_samples, write_csv
    from symgen.identification.regressor import make_problem
    from symgen.identification.states import random_states

    (folder / "empty.txt").write_text("")
    (folder / "dir").mkdir(exist_ok=True)
    (folder / "binary.bin").write_bytes(bytes(range(256)) * 4)
    (folder / "bad.csv").write_text("q_1,tau_1\n1,x\n,,,\n")
    (folder / "bad.yaml").write_text("name: [unclosed\nbodies: {a: 1\n")
    model = symgen.derive(symgen.load("chain:n=2"))
    write_csv(folder / "chain.csv", simulated_samples(make_problem(model), random_states(model, 12, seed=1),
                                                     noise=1e-3))
    return {"EMPTY": str(folder / "empty.txt"), "DIR": str(folder / "dir"), "BINARY": str(folder / "binary.bin"),
            "BADCSV": str(folder / "bad.csv"), "BADYAML": str(folder / "bad.yaml"), "CSV": str(folder / "chain.csv"),
            "URDF": str(DATA / "urdf" / "fixed_and_tilted.urdf")}


def run_cli_case(argv: list[str], folder: pathlib.Path) -> tuple[str, str | None]:
    """``(outcome, finding)``: the outcome's name (``parser refusal``, ``status 0/1/2``) and, for
    anything unacceptable, what was wrong (``None`` otherwise). Runs in ``folder``."""
    from symgen.cli import main

    out, err = io.StringIO(), io.StringIO()
    cwd = os.getcwd()
    os.chdir(folder)
    try:
        with time_bound(CLI_CASE_BOUND), contextlib.redirect_stdout(out), contextlib.redirect_stderr(err), \
                warnings.catch_warnings():
            warnings.simplefilter("ignore")
            try:
                status = main(list(argv))
            except SystemExit as exc:
                status = None if exc.code == 2 else exc.code
                if status is None:
                    text = err.getvalue()
                    if "Traceback" in text or "error:" not in text:
                        return "parser refusal", f"untidy parser refusal: {text[-300:]!r}"
                    return "parser refusal", None
    except CaseTimeout:
        return "hang", f"longer than {CLI_CASE_BOUND:g} s"
    except Exception as exc:  # noqa: BLE001 - every other exception is the finding
        return f"untyped {type(exc).__name__}", f"{type(exc).__name__}: {str(exc)[:300]}"
    finally:
        os.chdir(cwd)
    text = err.getvalue()
    if status not in (0, 1, 2):
        return f"exit {status!r}", f"unexpected exit status {status!r}"
    if "Traceback" in text:
        return f"status {status}", f"traceback on stderr: {text[-300:]!r}"
    if status == 2 and not (text.startswith("symgen: error: ") and text.count("\n") == 1):
        return "status 2", f"status 2 without one error line: {text[-300:]!r}"
    return f"status {status}", None
