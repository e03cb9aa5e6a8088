#!/usr/bin/env python3
"""Documentation rules of docs/README.md §4, checked over every file of the repository.

1. No file points outside the repository (the machine-local design and seed folders).
2. Every citation `docs/<note>.md §X` names an existing note and a section heading X in it.
3. Every `eq. (S.n)` / `eqs. (…)` after such a citation names an equation the note defines
   (a line of a ```text block ending in `(S.n)`); in docs/, a bare `§X` or `eq. (S.n)` refers to
   the note itself. Outside docs/, every § and every equation number belongs to a docs/ citation,
   and equations are never cited by a bare integer (the homework's numbering).
4. `<note>.md §X` is always written `docs/<note>.md §X`.
5. A note defines each equation number once, inside the top-level section S of its label.
6. README.md stays short: at most 200 lines, and without the generated parameter table (which
   docs/parameters.md holds); everything else lives in docs/.
7. A parameter's value stated beside its name in prose (`` `NAME` (0.5 s) `` or `` `NAME` = 2 ``,
   outside an enumeration such as `(0 = off)`) is its default in the generated table of
   docs/parameters.md, converted between the units both name (µs, ms, s; cm, m; %).

Prints `file:line: problem` for each violation and exits 1 if there is any. Standard library only.
"""

import pathlib
import re
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parents[1]
SKIPPED_PARTS = {"target", ".venv", ".git", "__pycache__", "node_modules"}
SKIPPED_PREFIXES = ("fuzz/corpus/", "fuzz/artifacts/", "fuzz/coverage/", "fuzz/target/", "runs/")

# Written so that this file does not match itself.
OUTSIDE = re.compile(r"/wor[k]/|shared/desig[n]|shared/see[d]|homework3[.]txt")

NUM = r"\d+(?:\.\d+)*"
SECTIONS = rf"§\s*{NUM}(?:\s*[–-]\s*§?\s*{NUM}|\s*(?:,|and)\s*§\s*{NUM})*"
CITATION = re.compile(rf"docs/([A-Za-z0-9_-]+\.md)\b(\s*{SECTIONS})?")
EQ_LIST = r"\(\d+\.\d+\)(?:\s*(?:,|–|-|and)\s*\(\d+\.\d+\))*"
EQ_AFTER = re.compile(rf"\s*,?\s*eqs?\.\s*({EQ_LIST})")
EQ_ANY = re.compile(rf"\beqs?\.\s*({EQ_LIST})")
EQ_INTEGER = re.compile(r"\beqs?\.\s*\(?\d+\)?(?![.\d])")
BARE_NOTE = re.compile(r"(?<![\w/.-])([A-Za-z0-9_-]+\.md)\s*§")
SECTION_TOKEN = re.compile(rf"§\s*({NUM})")
HEADING = re.compile(rf"^#{{1,6}}\s+({NUM})\.?\s")
LABEL = re.compile(r"\((\d+)\.(\d+)\)\s*$")
README_MAX_LINES = 200
PARAMS_MARKER = re.compile(r"<!--\s*params:(begin|end)")
PARAM_ROW = re.compile(r"^\| `([A-Z][A-Z0-9_]+)` \| \w+ \| ([^|]+?) \| [^|]*? \| ([^|]*?) \|")
PARAM_VALUE = re.compile(r"`([A-Z][A-Z0-9_]+)`\s*(?:\(|=\s*)(-?\d[\d ]*(?:\.\d+)?)(?![\d.]|\s*=)\s*([^\s,;)]*)")
# (unit in the prose, unit of the table) -> factor from the first to the second.
UNIT_FACTORS = {("s", "µs"): 1e6, ("ms", "µs"): 1e3, ("ms", "s"): 1e-3, ("µs", "s"): 1e-6,
                ("m", "cm"): 100.0, ("cm", "m"): 0.01, ("%", ""): 0.01, ("%", "-"): 0.01}


def repo_files():
    """Paths (relative, POSIX) of the files to check: git's view when available."""
    try:
        out = subprocess.run(
            ["git", "ls-files", "-z", "--cached", "--others", "--exclude-standard"],
            cwd=ROOT,
            capture_output=True,
            check=True,
        ).stdout.decode("utf-8", "replace")
        names = [n for n in out.split("\0") if n]
    except (OSError, subprocess.CalledProcessError):
        names = [p.relative_to(ROOT).as_posix() for p in ROOT.rglob("*") if p.is_file()]
    for name in sorted(set(names)):
        if SKIPPED_PARTS.intersection(name.split("/")) or name.startswith(SKIPPED_PREFIXES):
            continue
        path = ROOT / name
        if not path.is_file():
            continue
        try:
            text = path.read_text(encoding="utf-8")
        except (OSError, UnicodeDecodeError):
            continue
        if "\0" not in text:
            yield name, text


class Note:
    """Section headings and equation labels of one docs/*.md file."""

    def __init__(self, name, text, problems):
        self.sections = set()
        self.equations = set()
        fenced = False
        top = None
        for number, line in enumerate(text.splitlines(), 1):
            if line.lstrip().startswith("```"):
                fenced = not fenced
                continue
            if not fenced:
                m = HEADING.match(line)
                if m:
                    self.sections.add(m.group(1))
                    top = m.group(1).split(".")[0]
                continue
            m = LABEL.search(line)
            if m:
                label = f"{m.group(1)}.{m.group(2)}"
                if label in self.equations:
                    problems.append(f"{name}:{number}: equation ({label}) defined twice")
                if m.group(1) != top:
                    problems.append(
                        f"{name}:{number}: equation ({label}) is not in section {m.group(1)} (it is in §{top})"
                    )
                self.equations.add(label)


def expand(tokens):
    """Equation labels of a list such as `(5.1)–(5.3), (5.7)`; ranges within one section expand."""
    out = []
    parts = re.findall(r"\((\d+)\.(\d+)\)|([–-])", tokens)
    previous = None
    dash = False
    for s, n, d in parts:
        if d:
            dash = True
            continue
        if dash and previous and previous[0] == s:
            out.extend(f"{s}.{k}" for k in range(int(previous[1]) + 1, int(n)))
        out.append(f"{s}.{n}")
        previous, dash = (s, int(n)), False
    return out


def check_sections(where, note_name, note, tokens, problems):
    for section in SECTION_TOKEN.findall(tokens or ""):
        if section not in note.sections:
            problems.append(f"{where}: docs/{note_name} has no section §{section}")


def check_equations(where, note_name, note, tokens, problems):
    for label in expand(tokens):
        if label not in note.equations:
            problems.append(f"{where}: docs/{note_name} defines no equation ({label})")


def check_line(name, number, line, notes, problems):
    where = f"{name}:{number}"
    in_docs = name.startswith("docs/")
    own = notes.get(name[len("docs/"):]) if in_docs else None
    if OUTSIDE.search(line):
        problems.append(f"{where}: points outside the repository: {line.strip()}")
    for m in BARE_NOTE.finditer(line):
        problems.append(f"{where}: cite {m.group(1)} as docs/{m.group(1)}")
    covered = []
    for m in CITATION.finditer(line):
        note_name, sections = m.group(1), m.group(2)
        end = m.end()
        note = notes.get(note_name)
        if note is None:
            problems.append(f"{where}: docs/{note_name} does not exist")
            covered.append((m.start(), end))
            continue
        check_sections(where, note_name, note, sections, problems)
        eq = EQ_AFTER.match(line, end)
        if eq:
            check_equations(where, note_name, note, eq.group(1), problems)
            end = eq.end()
        covered.append((m.start(), end))

    def free(pos):
        return not any(a <= pos < b for a, b in covered)

    for m in SECTION_TOKEN.finditer(line):
        if not free(m.start()):
            continue
        if own is None:
            problems.append(f"{where}: section sign outside a docs/<note>.md citation: {line.strip()}")
        elif m.group(1) not in own.sections:
            problems.append(f"{where}: {name} has no section §{m.group(1)}")
    for m in EQ_ANY.finditer(line):
        if not free(m.start()):
            continue
        if own is None:
            problems.append(f"{where}: equation number outside a docs/<note>.md citation: {line.strip()}")
        else:
            check_equations(where, name[len("docs/"):], own, m.group(1), problems)
    if not in_docs:
        for m in EQ_INTEGER.finditer(line):
            problems.append(
                f"{where}: equation cited by a bare number (the homework's?); "
                f"cite docs/<note>.md §S, eq. (S.n): {line.strip()}"
            )


def check_readme(text, problems):
    """README.md is the front page: short, and the generated parameter table lives in docs/."""
    lines = text.splitlines()
    if len(lines) > README_MAX_LINES:
        problems.append(f"README.md: {len(lines)} lines, at most {README_MAX_LINES}")
    for number, line in enumerate(lines, 1):
        if PARAMS_MARKER.search(line):
            problems.append(
                f"README.md:{number}: the generated parameter table belongs in docs/parameters.md"
            )


def parameter_defaults(text):
    """{name: (default, unit)} from the generated table of docs/parameters.md."""
    table = {}
    for line in text.splitlines():
        m = PARAM_ROW.match(line)
        if m:
            table[m.group(1)] = (m.group(2).strip(), m.group(3).strip())
    return table


def check_defaults(name, number, line, defaults, problems):
    """Rule 7 on one line of prose."""
    for m in PARAM_VALUE.finditer(line):
        param, value, unit = m.group(1), m.group(2).replace(" ", ""), m.group(3)
        if param not in defaults:
            continue
        default, table_unit = defaults[param]
        try:
            expected, stated = float(default), float(value)
        except ValueError:
            continue
        if unit and unit != table_unit:
            factor = UNIT_FACTORS.get((unit, table_unit))
            if factor is None:
                continue
            stated *= factor
        if abs(stated - expected) > 1e-9 * max(1.0, abs(expected)):
            problems.append(f"{name}:{number}: `{param}` stated as {value} {unit}, but its default is "
                            f"{default} {table_unit} (docs/parameters.md)")


def main():
    problems = []
    files = list(repo_files())
    notes = {
        name[len("docs/"):]: Note(name, text, problems)
        for name, text in files
        if name.startswith("docs/") and name.endswith(".md") and "/" not in name[len("docs/"):]
    }
    defaults = parameter_defaults(dict(files).get("docs/parameters.md", ""))
    for name, text in files:
        prose = name.endswith(".md") and name != "docs/parameters.md"
        for number, line in enumerate(text.splitlines(), 1):
            check_line(name, number, line, notes, problems)
            if prose:
                check_defaults(name, number, line, defaults, problems)
        if name == "README.md":
            check_readme(text, problems)
    for p in problems:
        print(p, file=sys.stderr)
    if problems:
        print(f"docs_citations: {len(problems)} problem(s)", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
