"""The documentation site's sources: the generated pages agree with their data, every page is in the site,
every image a page shows exists, the API reference lists the declared public surface, and the build does not
depend on the network (the Sphinx build itself runs in .ci/run with -W)."""
import importlib.util
import json
import re
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"
GENERATED = ("_build", "api", "studies", "notebooks")
PAGES = sorted(p for p in DOCS.rglob("*.md") if p.relative_to(DOCS).parts[0] not in GENERATED)


def _module(path: Path, name: str):
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="module")
def generate():
    return _module(DOCS / "_generate.py", "docs_generate")


@pytest.fixture(scope="module")
def results_page():
    return _module(ROOT / "benchmarks" / "results_page.py", "benchmarks_results_page")


def test_the_benchmarks_page_is_generated_from_the_records(results_page, tmp_path):
    assert results_page.main(["--check"]) == 0
    page = tmp_path / "benchmarks.md"                         # a moved figure is caught
    page.write_text((DOCS / "benchmarks.md").read_text().replace("| 74.9 s |", "| 70.1 s |"))
    assert "| 74.9 s |" in (DOCS / "benchmarks.md").read_text()
    assert results_page.main(["--check", "--page", str(page)]) == 1


def test_every_record_states_command_commit_date_machine_load_and_figures():
    records = sorted((ROOT / "benchmarks" / "results").glob("*.json"))
    assert len(records) >= 29                                   # the old log's 28 sessions and the runs since
    for path in records:
        rec = json.loads(path.read_text())
        assert rec["id"] == path.stem and rec["title"], path.name
        assert re.match(r"20\d\d-\d\d-\d\d", rec["date"] or "") or path.stem.startswith("undated"), path.name
        assert isinstance(rec["commits"], list) and isinstance(rec["commands"], list), path.name
        assert "load" in rec and rec["machine"]["cores"] >= 1, path.name
        for f in rec["figures"]:
            assert {"name", "value", "unit"} <= set(f) and isinstance(f["value"], (int, float)), (path.name, f)
        if "text" not in rec:                                   # a run recorded since: stated in full
            assert rec["commands"] and rec["commits"] and rec["figures"] and rec["load"], path.name


def test_every_page_is_in_the_site_and_every_image_it_shows_exists():
    index = (DOCS / "index.md").read_text()
    listed = set(re.findall(r"^([\w/-]+)$", index, flags=re.M))
    for page in PAGES:
        name = str(page.relative_to(DOCS).with_suffix(""))
        assert name in listed or name in ("index", "newcomer-answers"), f"{name} is in no toctree of index.md"
        for image in re.findall(r"!\[[^\]]*\]\(([^)]+\.png)\)", page.read_text()):
            assert (page.parent / image).is_file(), (page.name, image)
    for image in re.findall(r"!\[[^\]]*\]\(([^)]+\.png)\)", (ROOT / "README.md").read_text()):
        assert (ROOT / image).is_file(), image


def test_the_api_reference_lists_the_declared_public_surface(generate, tmp_path):
    import bifurc
    import maps
    generate.api_pages(tmp_path)
    for module in (bifurc, maps):
        text = (tmp_path / "api" / f"{module.__name__}.rst").read_text()
        listed = re.findall(r"^   (\w+)$", text, flags=re.M)
        assert listed == [n for n in module.__all__ if not n.startswith("_")]
    pages = {"bifurc.studykit", "maps.studykit", "bifurc.labels", "bifurc.explore"}
    for name in pages:
        module = importlib.import_module(name)
        text = (tmp_path / "api" / f"{name}.rst").read_text()
        assert re.findall(r"^   (\w+)$", text, flags=re.M) == list(module._LAZY), name
        for n in module._LAZY:
            assert getattr(module, n) is not None
    index = (tmp_path / "api" / "index.rst").read_text()
    assert pages <= set(re.findall(r"^   ([\w.]+)$", index, flags=re.M))


def test_a_study_page_per_committed_report_with_its_command(generate, tmp_path):
    generate.study_pages(tmp_path, ROOT / "studies")
    reports = sorted(ROOT.glob("studies/*/report*.md"))
    pages = sorted((tmp_path / "studies").glob("*-*.md"))
    assert len(pages) == len(reports) >= 8
    atlas = (tmp_path / "studies" / "attractor_atlas-quick.md").read_text()
    assert "`bifurc study attractor-atlas --quick -o DIR`" in atlas and "studies/attractor_atlas/report-quick.md" in atlas


def test_intersphinx_leaves_out_what_it_cannot_reach(generate):
    """No network (as in CI): the inventory is left out, the build goes on."""
    assert generate.reachable_inventories({"nowhere": "http://127.0.0.1:9"}, timeout=0.5) == {}


def _cited(page: str) -> tuple[list, list, list, list]:
    """(paths, dotted names, missing paths, unresolved names) a page cites in backticks: a path has a "/" (from the
    repository's root, "<...>" placeholders cut off), a name is ``bifurc.`` or ``maps.`` dotted (a module, or an
    attribute of one)."""
    import importlib
    text = (ROOT / "docs" / page).read_text()
    cited = set(re.findall(r"`([^`\s]+)`", text))
    paths = sorted(c for c in cited if "/" in c)
    names = sorted(c for c in cited if re.fullmatch(r"(bifurc|maps)(\.\w+)+", c))

    def resolves(dotted):
        parts = dotted.split(".")
        for k in range(len(parts), 0, -1):
            try:
                obj = importlib.import_module(".".join(parts[:k]))
            except ImportError:
                continue
            try:
                for attr in parts[k:]:
                    obj = getattr(obj, attr)
            except AttributeError:
                return False
            return True
        return False
    return (paths, names, [p for p in paths if not (ROOT / p.split("<")[0]).exists()],
            [n for n in names if not resolves(n)])


def test_the_architecture_page_cites_only_modules_and_names_that_exist():
    """docs/architecture.md is the one description of the layout: every backticked path exists and every
    backticked dotted name of ``bifurc`` or ``maps`` resolves (a module, or an attribute of one)."""
    paths, names, missing, unresolved = _cited("architecture.md")
    assert len(paths) > 40 and len(names) > 15, (len(paths), len(names))
    assert not missing, missing
    assert not unresolved, unresolved


def test_the_duplicates_page_cites_only_files_and_names_that_exist():
    """docs/explanation/duplicates.md (review 4's duplicated rules, where each lives now): every file it cites
    exists and every ``module.name`` resolves, so a rule moved or renamed fails here until the table follows."""
    paths, names, missing, unresolved = _cited("explanation/duplicates.md")
    assert len(paths) >= 8 and len(names) >= 60, (len(paths), len(names))
    assert not missing, missing
    assert not unresolved, unresolved
    text = (ROOT / "docs" / "explanation" / "duplicates.md").read_text()
    rows = re.findall(r"^\| (N\d|D\d+) \|", text, flags=re.M)
    assert rows == ["N1", "N2", "N3", "N4", "N5", "N6", "N7", "D1", "D2", "D3", "D5", "D8", "D9", "D11", "D12",
                    "D15"], rows


def _cited_tests(page: str) -> tuple:
    """The tests a page cites: ``tests/FILE.py::name`` (``::name`` alone continues the last file of its line), a bare
    ``test_name``, and ``tests/FILE.py``; returns (cited, missing), a parametrized id's ``[...]`` ignored."""
    import ast
    defined = {p.name: {n.name for n in ast.walk(ast.parse(p.read_text())) if isinstance(n, ast.FunctionDef)}
               for p in (ROOT / "tests").glob("test_*.py")}
    everywhere = set().union(*defined.values())
    cited, missing = [], []
    for line in (DOCS / page).read_text().splitlines():
        current = None
        for ref in re.findall(r"`([^`]+)`", line):
            if m := re.fullmatch(r"tests/(test_\w+\.py)(?:::(\w+)(?:\[[^\]]*\])?)?", ref):
                current, name = m.group(1), m.group(2)
                cited.append(ref)
                if current not in defined or (name and name not in defined[current]):
                    missing.append(ref)
            elif m := re.fullmatch(r"::(test_\w+)(?:\[[^\]]*\])?", ref):
                cited.append(f"{current}{ref}")
                if current not in defined or m.group(1) not in defined[current]:
                    missing.append(f"{current}{ref}")
            elif m := re.fullmatch(r"(test_\w+)(?:\[[^\]]*\])?", ref):
                cited.append(ref)
                if m.group(1) not in everywhere:
                    missing.append(ref)
    return cited, missing


def test_the_newcomer_answers_cite_tests_that_exist_and_answer_every_finding_of_review_4():
    """docs/newcomer-answers.md names, for each finding, the test that covers it: every cited test file and test
    function exists (a renamed test fails here until the page follows), and its section on review 4 has one row per
    finding G1-G14 and the time coordinate, each citing a test."""
    cited, missing = _cited_tests("newcomer-answers.md")
    assert len(cited) > 60 and not missing, missing
    text = (DOCS / "newcomer-answers.md").read_text()
    section = text[text.index("## Review 4 (G1-G14)"):]
    section = section[:section.find("\n## ", 1)] if "\n## " in section[1:] else section
    rows = re.findall(r"^\| (G\d+|time coordinate)\b[^|]*\|[^|]*\|(.*)\|$", section, flags=re.M)
    assert [r[0] for r in rows] == [f"G{i}" for i in range(1, 15)] + ["time coordinate"], [r[0] for r in rows]
    assert all("tests/" in test for _, test in rows), [g for g, test in rows if "tests/" not in test]
