#!/usr/bin/env bash
# Cross-checks m2rc's LTLf -> DFA construction against an independent tool: MONA (Debian `mona`)
# through LTLf2DFA (PyPI `ltlf2dfa`), on the robotic mission specification patterns (visit,
# sequenced visit, ordered visit, strict ordered visit, avoidance, until, reactions, and their
# conjunctions) over 1-4 atoms. Two automata agree when they accept the same non-empty finite
# traces (checked exactly, by a breadth-first search of their product over every letter).
#
# Not part of CI's required path (it installs system and Python packages). Usage:
#   scripts/ltl-crosscheck.sh [path/to/m2rc]
# Prints one line per formula and `N/M agree` at the end; exits non-zero on any disagreement.
set -euo pipefail
M2RC="${1:-target/debug/m2rc}"
if ! command -v mona >/dev/null; then
  apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq mona
fi
VENV="${LTLF_VENV:-/tmp/ltlf-venv}"
if [ ! -x "$VENV/bin/python" ]; then
  python3 -m venv "$VENV"
  "$VENV/bin/pip" install -q ltlf2dfa
fi
exec "$VENV/bin/python" - "$M2RC" <<'PY'
import itertools, json, re, subprocess, sys
from ltlf2dfa.parser.ltlf import LTLfParser

m2rc = sys.argv[1]

def seq(ls):
    f = ls[-1]
    for l in reversed(ls[:-1]):
        f = f"{l} & F({f})"
    return f"F({f})" if len(ls) > 1 else f"F {ls[0]}"

def patterns():
    atoms = ["a", "b", "c", "d"]
    out = []
    for n in range(1, 4):
        ls = atoms[:n]
        out.append(("visit", " & ".join(f"F {l}" for l in ls)))
        out.append(("sequenced visit", seq(ls)))
        if n >= 2:
            order = " & ".join(f"(!{ls[i+1]} U {ls[i]})" for i in range(n - 1))
            out.append(("ordered visit", f"{seq(ls)} & {order}"))
            strict = " & ".join(
                f"(!{ls[i]} U ({ls[i]} & X(!{ls[i]} U {ls[i+1]})))" for i in range(n - 1))
            out.append(("strict ordered visit", f"{seq(ls)} & {order} & {strict}"))
        avoid = "d"
        out.append(("avoidance", f"G !{avoid}"))
        out.append(("visit + avoidance", " & ".join(f"F {l}" for l in ls) + f" & G !{avoid}"))
        out.append(("sequenced visit + avoidance", f"{seq(ls)} & G !{avoid}"))
        if n >= 2:
            out.append(("until", f"{ls[0]} U {ls[1]}"))
            out.append(("stage-scoped avoidance", f"(!{ls[0]} & !{avoid}) U ({ls[0]} & !{avoid} & F {ls[1]})"))
            out.append(("instantaneous reaction", f"G({ls[0]} -> {ls[1]})"))
            out.append(("delayed reaction", f"G({ls[0]} -> F {ls[1]})"))
            out.append(("ordered visit + avoidance", f"{seq(ls)} & {order} & G !{avoid}"))
    out.append(("release", "a R b"))
    out.append(("weak next", "G(a -> WX b)"))
    seen, uniq = set(), []
    for name, f in out:
        if f not in seen:
            seen.add(f)
            uniq.append((name, f))
    return uniq

def guard_fn(text, atoms):
    expr = text.replace("~", " not ").replace("!", " not ").replace("&", " and ").replace("|", " or ")
    expr = re.sub(r"\btrue\b", "True", expr)
    expr = re.sub(r"\bfalse\b", "False", expr)
    code = compile(expr.strip(), "<guard>", "eval")
    return lambda letter: bool(eval(code, {}, dict(letter)))

def mine(formula, atoms):
    out = subprocess.run([m2rc, "ltl", formula, "--emit", "dfa", "--atoms", ",".join(atoms)],
                         capture_output=True, text=True)
    if out.returncode != 0:
        raise RuntimeError(out.stderr)
    d = json.loads(out.stdout)
    edges = {}
    for e in d["edges"]:
        edges.setdefault(e["from"], []).append((guard_fn(e["guard"], atoms), e["to"]))
    return d["initial"], set(d["accepting"]), edges

def theirs(formula, atoms):
    dot = LTLfParser()(formula).to_dfa()
    init = int(re.search(r"init\s*->\s*(\d+)", dot).group(1))
    acc = set()
    m = re.search(r"node \[shape = doublecircle\];([^\n]*)", dot)
    if m:
        acc = {int(x) for x in re.findall(r"\d+", m.group(1))}
    edges = {}
    for a, b, label in re.findall(r"(\d+)\s*->\s*(\d+)\s*\[label=\"([^\"]*)\"\]", dot):
        edges.setdefault(int(a), []).append((guard_fn(label, atoms), int(b)))
    return init, acc, edges

def step(edges, q, letter):
    if q is None:
        return None
    for g, to in edges.get(q, []):
        if g(letter):
            return to
    return None

def equivalent(x, y, atoms):
    (i1, a1, e1), (i2, a2, e2) = x, y
    letters = [dict(zip(atoms, bits)) for bits in itertools.product([False, True], repeat=len(atoms))]
    start = [(step(e1, i1, l), step(e2, i2, l)) for l in letters]
    seen, queue = set(start), list(start)
    while queue:
        p, q = queue.pop()
        if (p in a1) != (q in a2):
            return False
        for l in letters:
            n = (step(e1, p, l), step(e2, q, l))
            if n not in seen:
                seen.add(n)
                queue.append(n)
    return True

agree = total = 0
for name, f in patterns():
    atoms = sorted(set(re.findall(r"\b[a-d]\b", f)))
    total += 1
    try:
        ok = equivalent(mine(f, atoms), theirs(f, atoms), atoms)
    except Exception as e:  # a tool failure counts as a disagreement, with the reason
        print(f"ERROR  {name}: {f}: {e}")
        continue
    agree += ok
    print(f"{'agree ' if ok else 'DIFFER'} {name}: {f}")
print(f"{agree}/{total} agree")
sys.exit(0 if agree == total else 1)
PY
