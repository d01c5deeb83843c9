"""The one option table (apps/run_options.cpp, as vmas.options() gives it) against what repeats
it: docs/cli.md's options of `vmas skeletonize`, vmas.pyi's RunOptions, `vmas skeletonize
--help`, and the ranges validate() enforces. Run by ctest (VMAS_CLI: the vmas binary)."""

import ast
import os
import re
import subprocess

import pytest

import vmas

VMAS_CLI = os.environ.get("VMAS_CLI", "")
ROOT = os.path.join(os.path.dirname(__file__), "..", "..")
ROWS = vmas.options()
# Keywords that are parameters of their own (skeletonize(points, ..., spheres=, error=,
# threads=)) or not keywords at all (a density field is read with vmas.read).
OWN_PARAMETERS = {"spheres", "error", "threads"}
NOT_KEYWORDS = {"density_field"}


def cli_rows():
    """docs/cli.md's table of `vmas skeletonize`: {long flag: default as written}."""
    with open(os.path.join(ROOT, "docs", "cli.md")) as f:
        text = f.read()
    section = text.split("## `vmas skeletonize")[1].split("\n## ")[0]
    rows = {}
    for line in section.splitlines():
        match = re.match(r"\| `(?:-\w, )?--([\w-]+)[^`]*` \| ([^|]*) \|", line)
        if match:
            rows[match.group(1)] = match.group(2).strip()
    return rows


def help_flags():
    """The long flags `vmas skeletonize --help` lists."""
    shown = subprocess.run([VMAS_CLI, "skeletonize", "--help"], capture_output=True, text=True,
                           check=True).stdout
    return set(re.findall(r"^\s+(?:-\w \[ )?--([\w-]+)", shown, re.MULTILINE))


def same_default(written, row):
    """Whether docs/cli.md's default column says what the table's default is."""
    if row["type"] == "bool":
        return written == "off"
    if row["default"] is None:
        # No default of the parser's: the column names the one the library picks, which the
        # help text states ("default 100 when --error is absent"), or none at all.
        return written == "—" or f"default {written}" in row["help"]
    first = written.split(" ")[0]
    if row["type"] == "str":
        return first == row["default"]
    return float(first) == float(row["default"])


def test_every_option_is_in_the_table_and_in_the_docs():
    assert len(ROWS) >= 25
    documented = cli_rows()
    for row in ROWS:
        name = row["flag"][2:]
        assert name in documented, f"docs/cli.md has no row for {row['flag']}"
        assert same_default(documented[name], row), \
            f"{row['flag']}: docs/cli.md says {documented[name]!r}, the table {row['default']!r}"
    if VMAS_CLI:
        # The table's rows are all the run's options --help shows; the others are the command's own.
        listed = help_flags()
        table = {row["flag"][2:] for row in ROWS}
        assert table <= listed
        assert set(documented) == listed - {"help"}, set(documented) ^ (listed - {"help"})


def test_the_stubs_list_every_keyword_with_its_type():
    with open(os.path.join(ROOT, "apps", "python", "vmas.pyi")) as f:
        module = ast.parse(f.read())
    stub = next(node for node in module.body
                if isinstance(node, ast.ClassDef) and node.name == "RunOptions")
    annotations = {node.target.id: ast.unparse(node.annotation) for node in stub.body
                   if isinstance(node, ast.AnnAssign)}
    keywords = {row["keyword"]: row for row in ROWS
                if row["keyword"] not in OWN_PARAMETERS | NOT_KEYWORDS}
    assert set(annotations) == set(keywords)
    for keyword, row in keywords.items():
        assert row["type"] in annotations[keyword], (keyword, row["type"], annotations[keyword])


def probes(row):
    """(value, accepted) pairs at and just past each end of the row's range."""
    integer = row["type"] == "int"
    step = (lambda x: 1) if integer else (lambda x: max(abs(x) * 1e-6, 1e-9))
    shown = (lambda x: str(int(x))) if integer else repr
    pairs = []
    for part in row["range"].split(" | "):
        if re.fullmatch(r"[a-z]+", part):
            pairs.append((part, True))
            continue
        match = re.fullmatch(r">= (\S+)", part)
        if match:
            low = float(match.group(1))
            pairs += [(shown(low), True), (shown(low - step(low)), False)]
            continue
        match = re.fullmatch(r"([\[(])(\S+), (\S+)([\])])", part)
        if match:
            low, high = float(match.group(2)), float(match.group(3))
            pairs += [(shown(low), match.group(1) == "["), (shown(high), match.group(4) == "]"),
                      (shown(low - step(low)), False), (shown(high + step(high)), False)]
            if match.group(1) == "(":
                pairs.append((shown(low + step(low)), True))
            if match.group(4) == ")":
                pairs.append((shown(high - step(high)), True))
            continue
        if re.fullmatch(r"\d+", part):
            pairs.append((part, True))
            continue
        pytest.fail(f"{row['flag']}: a range the test cannot read: {part!r}")
    return pairs


@pytest.mark.skipif(not VMAS_CLI, reason="VMAS_CLI (the vmas binary) is not set")
def test_the_ranges_are_what_validate_accepts(tmp_path):
    ranged = [row for row in ROWS if row["range"]]
    assert len(ranged) >= 20
    missing = str(tmp_path / "missing.off")  # accepted options fail later, on the input
    for row in ranged:
        for value, accepted in probes(row):
            # The default count (100) would be refused above a small --max-spheres.
            context = ["--error", "0.01"] if row["flag"] == "--max-spheres" else []
            run = subprocess.run([VMAS_CLI, "skeletonize", missing, "-o", str(tmp_path / "o.ply"),
                                  row["flag"], value] + context, capture_output=True, text=True)
            if accepted:
                assert run.returncode == 1 and "no such file" in run.stderr, \
                    f"{row['flag']} {value} (range {row['range']}): {run.stderr}"
            else:
                # Rejected as a usage error that names the flag (flag_of of the field).
                assert run.returncode == 2 and row["flag"] in run.stderr, \
                    f"{row['flag']} {value} (range {row['range']}): {run.stderr}"
