"""Hand-written bad inputs: each must give one line ``evoplan: error: ...``, exit 2, and no folder.

A case is ``(id, command, file text or bytes, extra arguments)``; the file is written to a
temporary folder as ``case.yaml`` and the command run in-process with ``--out`` pointing at a
folder that must still not exist afterwards. The generic cases are applied to every command's
file; the specific ones probe one command's settings.
"""

from __future__ import annotations

RUN = """seed: 1
problem: {name: kubota, bits: 12}
algorithm: {name: ga, population: 8}
termination: {generations: 2}
output: {plot: false}
"""

STUDY = """seed: 1
seeds: 2
budget: {evaluations: 40}
problems: [{name: kubota}]
algorithms: [{name: ga, population: 8}]
"""

ZONE = """surface: choi
mesh: [12, 12]
method: kmeans
kmeans: {K: 2}
sample_spacing: 1.0
direction_scan: 2
"""

# modules a test writes on sys.path: user code that fails while being imported
USER_MODULES = {
    "h14_raises": "raise RuntimeError('broken at import')\n",
    "h14_syntax": "def broken(:\n",
    "h14_exits": "import sys\nsys.exit(3)\n",
}

# a small machining job (a 40 x 30 mm Bezier patch), written here in flow style
MACHINE = ("name: small\n"
           "surface: {type: bezier, poles: [[[0, 0, 0], [0, 15, 4], [0, 30, 0]], [[20, 0, 4], [20, 15, 14], "
           "[20, 30, 4]], [[40, 0, 0], [40, 15, 4], [40, 30, 0]]]}\n"
           "stock: {cell: 1.0}\n"
           "roughing: {method: zlevel, max_depth: 3.0, tool: {diameter: 8}}\n"
           "semifinish: {stepover: 4, step: 3}\n"
           "finish: {params: {tool: 8, stepover: 40, lead: 2, tilt: 0, step: 8}}\n"
           "post: {dialect: heidenhain, kinematics: {tilt: {name: B, about: y, limits: [-90, 90]}, "
           "layout: head_table}}\n")

# a toolpath run file for simulate (its plan given by --set)
SIMULATE = RUN.replace("name: kubota, bits: 12", "name: toolpath, bits: 8")
SIM_SETS = ["--set", "tool=8", "--set", "stepover=30.0", "--set", "lead=1.0", "--set", "tilt=0.5", "--set", "step=8.0"]

GOOD = {"run": RUN, "evaluate": RUN, "study": STUDY, "zone": ZONE, "machine": MACHINE}

BOMB = "a: &a [x, x, x, x, x, x, x, x, x]\n" + "".join(
    f"{chr(98 + i)}: &{chr(98 + i)} [{', '.join(['*' + chr(97 + i)] * 9)}]\n" for i in range(9))

GENERIC = [
    ("binary", b"\x89PNG\r\n\x1a\n\x00\x00\x00\rIHDR"),
    ("latin-1", "seed: 1\nname: caf\u00e9\n".encode("latin-1")),
    ("utf-16", "seed: 1\n".encode("utf-16")),
    ("alias bomb", BOMB),
    ("20000 levels", "a: " + "[" * 20000 + "]" * 20000 + "\n"),
    ("deep mappings", "a: " + "{b: " * 200 + "1" + "}" * 200 + "\n"),
    ("duplicate top key", None),  # the command's good file with its first line repeated
    ("empty", ""),
    ("top-level list", "- 1\n- 2\n"),
    ("top-level scalar", "just text\n"),
    ("bad syntax", "a: [1, 2\nb: }\n"),
    ("tab indentation", "problem:\n\tname: kubota\n"),
    ("huge key", None),  # the good file plus an unknown key of 100000 characters
    ("huge value", None),  # the good file with the name replaced by 1000000 characters
    ("python tag", "seed: !!python/object/apply:os.system ['true']\n"),
    ("unknown key", None),  # the good file plus an unknown top-level key
]


def generic_text(case: str, good: str):
    if case == "duplicate top key":
        return good + good.splitlines()[0] + "\n"
    if case == "huge key":
        return good + "k" * 100_000 + ": 1\n"
    if case == "huge value":
        return good + "name: " + "n" * 1_000_000 + "\n"
    if case == "unknown key":
        return good + "frobnicate: 3\n"
    raise KeyError(case)


SPECIFIC = [
    ("run", "seconds .inf alone", RUN.replace("{generations: 2}", "{seconds: .inf}"), []),
    ("run", "generations .nan", RUN.replace("{generations: 2}", "{generations: .nan}"), []),
    ("run", "target .nan", RUN.replace("{generations: 2}", "{generations: 2, target: .nan}"), []),
    ("run", "pressure .inf", RUN.replace("population: 8}", "population: 8, fitness: {pressure: .inf}}"), []),
    ("run", "penalty .nan", RUN.replace("bits: 12}", "bits: 12, constraint_penalty: .nan}"), []),
    ("run", "bound .inf", RUN.replace("bits: 12}", "bits: 12, variables: {x: {high: .inf}}}"), []),
    ("run", "population 10^12", RUN.replace("population: 8", "population: 1000000000000"), []),
    ("run", "population -3", RUN.replace("population: 8", "population: -3"), []),
    ("run", "population as text", RUN.replace("population: 8", "population: many"), []),
    ("run", "bits 0", RUN.replace("bits: 12", "bits: 0"), []),
    ("run", "bits 10^6", RUN.replace("bits: 12", "bits: 1000000"), []),
    ("run", "seed negative", RUN.replace("seed: 1", "seed: -1"), []),
    ("run", "seed huge", RUN.replace("seed: 1", "seed: " + "9" * 5000), []),
    ("run", "scheduler with serial", RUN + "evaluation: {scheduler: 'tcp://127.0.0.1:1'}\n", []),
    ("run", "timeout with serial", RUN + "evaluation: {timeout_s: 5}\n", []),
    ("run", "workers 0", RUN + "evaluation: {backend: processes, workers: 0}\n", []),
    ("run", "unreachable scheduler", RUN + "evaluation: {backend: dask, scheduler: 'tcp://127.0.0.1:9'}\n", []),
    ("run", "no termination", RUN.replace("termination: {generations: 2}\n", ""), []),
    ("run", "target alone", RUN.replace("{generations: 2}", "{target: 0.0}"), []),
    ("run", "problem subprocess:run", RUN.replace("name: kubota", "name: 'subprocess:run'"), []),
    ("run", "problem os:system", RUN.replace("name: kubota", "name: 'os:system'"), []),
    ("run", "problem builtins:eval", RUN.replace("name: kubota", "name: 'builtins:eval'"), []),
    ("run", "problem module raises", RUN.replace("name: kubota", "name: 'h14_raises:P'"), []),
    ("run", "problem module syntax", RUN.replace("name: kubota", "name: 'h14_syntax:P'"), []),
    ("run", "problem module exits", RUN.replace("name: kubota", "name: 'h14_exits:P'"), []),
    ("run", "problem not a class", RUN.replace("name: kubota", "name: 'os.path:join'"), []),
    ("run", "problem missing module", RUN.replace("name: kubota", "name: 'no_such_module_xyz:P'"), []),
    ("run", "problem empty class", RUN.replace("name: kubota", "name: 'os.path:'"), []),
    ("run", "problem unknown", RUN.replace("name: kubota", "name: no_such_problem"), []),
    ("run", "params not a mapping", RUN.replace("bits: 12}", "bits: 12, params: [1, 2]}"), []),
    ("run", "params unknown", RUN.replace("bits: 12}", "bits: 12, params: {zzz: 1}}"), []),
    ("run", "algorithm unknown", RUN.replace("name: ga", "name: gaa"), []),
    ("run", "algorithm missing", RUN.replace("name: ga, ", ""), []),
    ("run", "elitism >= population", RUN.replace("population: 8}", "population: 8, elitism: 8}"), []),
    ("run", "set malformed", RUN, ["--set", "algorithm.population=["]),
    ("run", "set no equals", RUN, ["--set", "algorithm.population"]),
    ("run", "set through scalar", RUN, ["--set", "seed.x=1"]),
    ("run", "set bomb", RUN, ["--set", "name=" + BOMB.replace("\n", "; ")]),
    ("run", "argparse unknown option", RUN, ["--frobnicate"]),
    ("run", "argparse bad seed", RUN, ["--seed", "abc"]),
    ("run", "control net outside", RUN.replace("name: kubota, bits: 12", "name: toolpath, bits: 8, "
                                               "params: {surface: {type: bezier, poles: /etc/passwd}}"), []),
    ("run", "control net csv with secrets", None, []),  # written by the test: a csv whose line is a secret
    ("run", "folded surface", RUN.replace("name: kubota, bits: 12", "name: toolpath, bits: 8, params: {surface: "
                                          "{type: bezier, poles: [[[0,0,0],[0,100,0]],[[100,0,0],[100,100,0]],"
                                          "[[-50,0,0],[-50,100,0]],[[100,0,0],[100,100,0]]]}}"), []),
    ("run", "vertical wall", RUN.replace("name: kubota, bits: 12", "name: toolpath, bits: 8, params: {surface: "
                                         "{type: bspline, degree: [1, 1], poles: [[[0,0,0],[0,100,0]],"
                                         "[[50,0,0],[50,100,0]],[[50,0,50],[50,100,50]],[[100,0,50],[100,100,50]]]}}"),
     []),
    ("evaluate", "set malformed", RUN, ["--set", "x=["]),
    ("evaluate", "set unknown variable", RUN, ["--set", "zz=1"]),
    ("zone", "negative K-means weight", ZONE.replace("kmeans: {K: 2}", "kmeans: {K: 2, weights: [1, -1, 1, 1]}"), []),
    ("zone", "mesh 200000 x 200000", ZONE.replace("[12, 12]", "[200000, 200000]"), []),
    ("zone", "h_c .nan", ZONE + "h_c: .nan\n", []),
    ("zone", "cutter R .inf", ZONE + "cutter: {R: .inf, r: 1}\n", []),
    ("study", "seeds 0", STUDY.replace("seeds: 2", "seeds: 0"), []),
    ("study", "budget .inf", STUDY.replace("{evaluations: 40}", "{evaluations: .inf}"), []),
    ("study", "scheduler with processes", STUDY, ["--backend", "processes", "--scheduler", "tcp://x:1"]),
    ("study", "workers 0", STUDY, ["--backend", "processes", "--workers", "0"]),
    ("study", "unknown algorithm", STUDY.replace("name: ga", "name: nope"), []),
    # settings that size an allocation or a count: refused with the number before any work
    ("machine", "kinematics max_step 1e-9", MACHINE.replace("layout: head_table}", "layout: head_table, max_step: 1.0e-9}"), []),
    ("machine", "max_depth 1e-7", MACHINE.replace("max_depth: 3.0", "max_depth: 1.0e-7"), []),
    ("machine", "stock.cell 1e-5", MACHINE.replace("{cell: 1.0}", "{cell: 1.0e-5}"), []),
    # found by the fuzzer: cell counts past what a float holds (an int overflow, a traceback)
    ("machine", "stock.cell 1e-300", MACHINE.replace("{cell: 1.0}", "{cell: 1.0e-300}"), []),
    # found by the fuzzer: a list of mappings of long strings echoed whole (a 602-character line)
    ("machine", "finish a list of long mappings", MACHINE.replace(
        "finish: {params: {tool: 8, stepover: 40, lead: 2, tilt: 0, step: 8}}",
        "finish: [" + ", ".join(["{" + ", ".join(f"k{i}{'x' * 50}: {'v' * 60}" for i in range(4)) + "}"] * 3) + "]"), []),
    ("machine", "roughing tool diameter 5000", MACHINE.replace("tool: {diameter: 8}", "tool: {diameter: 5000}"), []),
    ("machine", "semifinish.step 1e-6", MACHINE.replace("stepover: 4, step: 3", "stepover: 4, step: 1.0e-6"), []),
    ("simulate", "grid 1e-300", SIMULATE, [*SIM_SETS, "--grid", "1e-300"]),
    ("simulate", "grid 1e6", SIMULATE, [*SIM_SETS, "--grid", "1e6"]),
    ("study", "seeds 1e12", STUDY.replace("seeds: 2", "seeds: 1000000000000"), []),
    ("study", "seeds 1e5 x many problems", STUDY.replace("seeds: 2", "seeds: 100000").replace(
        "problems: [{name: kubota}]", "problems: [{name: rastrigin, dimensions: [1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11]}]"), []),
    ("study", "factor with no levels", STUDY + "factors: {algorithm: ga, vary: {population: []}}\n", []),
    ("study", "timeout_s 0", STUDY + "evaluation: {timeout_s: 0}\n", []),
    ("evaluate", "duplicate --set", RUN, ["--set", "x=0", "--set", "x=1", "--set", "y=0"]),
    ("run", "duplicate --set", RUN, ["--set", "seed=1", "--set", "seed=2"]),
]
