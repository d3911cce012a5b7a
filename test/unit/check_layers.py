"""The folders of src/ as layers: each folder may use only folders below it.

Maps every `use` of a module in src/ (Fortran sources and fypp templates) to the folder that
defines the module, and checks the folder graph:
  - it has no cycle (a folder never reaches itself through the modules it uses);
  - src/core uses no module outside src/core;
  - no scene kind is named outside src/scene (a quoted kind name in the code of src/ or app/, comments
    left out): what differs between kinds is each kind's input's to say (src/scene);
  - the layers table in docs/development.md (between the markers `<!-- layers -->` and
    `<!-- /layers -->`) is the one this script prints (`--write` rewrites it).
Prints the layers bottom-up: each folder with its level (1 + the highest level it uses) and what it
uses. Exit status 0 when every check passes, 1 otherwise (each failure named).

    .venv/bin/python test/unit/check_layers.py            # check
    .venv/bin/python test/unit/check_layers.py --write    # rewrite the table in docs/development.md
"""
import argparse
import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
SRC = ROOT / "src"
DOC = ROOT / "docs" / "development.md"
BEGIN, END = "<!-- layers -->", "<!-- /layers -->"
MODULE = re.compile(r"\s*module\s+(?!procedure\b|subroutine\b|function\b)(\w+)\s*$", re.I)
USE = re.compile(r"\s*use\s*(?:,\s*\w+\s*::)?\s*(\w+)", re.I)


def sources(src):
    return sorted(p for p in src.rglob("*") if p.suffix in (".f90", ".fypp", ".fypi"))


def folder_graph(src=SRC):
    """{folder: {folder it uses: [(file, module), ...]}} over the folders of src/."""
    owner, uses = {}, []
    for path in sources(src):
        folder = path.relative_to(src).parts[0]
        for line in path.read_text(errors="replace").splitlines():
            code = line.split("!")[0]
            m = MODULE.match(code)
            if m:
                owner[m.group(1).lower()] = folder
            m = USE.match(code)
            if m:
                uses.append((folder, path.relative_to(src).as_posix(), m.group(1).lower()))
    graph = {p.name: {} for p in src.iterdir() if p.is_dir()}
    for folder, file, module in uses:
        target = owner.get(module)
        if target is not None and target != folder:
            graph.setdefault(folder, {}).setdefault(target, []).append((file, module))
    return graph


def cycles(graph):
    """The folders that reach themselves, each with one path back to itself."""
    found = {}
    for start in graph:
        stack, seen = [(start, [start])], set()
        while stack:
            node, path = stack.pop()
            for nxt in graph.get(node, {}):
                if nxt == start:
                    found.setdefault(start, path + [start])
                elif nxt not in seen:
                    seen.add(nxt)
                    stack.append((nxt, path + [nxt]))
    return found


def levels(graph):
    """Level of each folder: 1 + the highest level of the folders it uses (0: uses none)."""
    level = {}

    def of(folder, visiting=()):
        if folder in level:
            return level[folder]
        if folder in visiting:  # a cycle: reported elsewhere
            return 0
        below = [of(t, visiting + (folder,)) for t in graph.get(folder, {})]
        level[folder] = 1 + max(below) if below else 0
        return level[folder]

    for folder in graph:
        of(folder)
    return level


def table(graph):
    level = levels(graph)
    rows = ["| level | folder | uses |", "|---|---|---|"]
    for folder in sorted(graph, key=lambda f: (level[f], f)):
        used = ", ".join(f"`{t}`" for t in sorted(graph[folder], key=lambda t: (level[t], t))) or "nothing"
        rows.append(f"| {level[folder]} | `src/{folder}/` | {used} |")
    return "\n".join(rows)


def scene_kinds(src=SRC):
    """The kinds the scene modules describe (scene_kind_t('name', ...))."""
    kinds = set()
    for path in (src / "scene").glob("*.f90"):
        kinds.update(re.findall(r"scene_kind_t\(\s*'(\w+)'", path.read_text()))
    return kinds


def kinds_named_outside(src=SRC, app=ROOT / "app"):
    """[(file, line number, kind)] of quoted scene kind names in code outside src/scene."""
    kinds = scene_kinds(src)
    found = []
    for path in sources(src) + sorted(app.glob("*.f90")):
        if path.is_relative_to(src / "scene"):
            continue
        for number, line in enumerate(path.read_text(errors="replace").splitlines(), 1):
            code = line.split("!")[0]
            for kind in kinds:
                if re.search(r"['\"]" + kind + r"['\"]", code):
                    found.append((path.relative_to(ROOT).as_posix(), number, kind))
    return found


def doc_table(text):
    if BEGIN not in text or END not in text:
        return None
    return text.split(BEGIN, 1)[1].split(END, 1)[0].strip()


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--write", action="store_true", help="rewrite the table in docs/development.md")
    args = parser.parse_args(argv)
    graph = folder_graph()
    failures = []
    for folder, path in sorted(cycles(graph).items()):
        failures.append(f"folder {folder} is in an import cycle: " + " -> ".join(path)
                        + " (" + "; ".join(f"{f} uses {m}" for a, b in zip(path, path[1:])
                                           for f, m in graph[a][b][:1]) + ")")
    for target, places in sorted(graph.get("core", {}).items()):
        failures.append(f"src/core uses src/{target}: " + ", ".join(f"{f} uses {m}" for f, m in places))
    if not scene_kinds():
        failures.append("no scene kind found in src/scene (scene_kind_t('name', ...))")
    for file, number, kind in kinds_named_outside():
        failures.append(f"{file}:{number} names scene kind '{kind}' outside src/scene")
    text = table(graph)
    print(text)
    doc = DOC.read_text()
    if args.write:
        if doc_table(doc) is None:
            failures.append(f"{DOC} has no {BEGIN} ... {END} markers")
        else:
            head, rest = doc.split(BEGIN, 1)
            DOC.write_text(head + BEGIN + "\n" + text + "\n" + END + rest.split(END, 1)[1])
    elif doc_table(doc) != text:
        failures.append(f"the layers table in {DOC.relative_to(ROOT)} is not the graph of src/: "
                        "run .venv/bin/python test/unit/check_layers.py --write")
    for f in failures:
        print("FAIL " + f)
    if not failures:
        print(f"ok   {len(graph)} folders of src/ in layers, no cycle; src/core uses nothing outside it; "
              f"no scene kind ({len(scene_kinds())}) named outside src/scene")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
