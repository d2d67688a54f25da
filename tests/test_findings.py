"""Findings that cannot go stale: a report's findings table reads back what was written, a moved
number or label fails the comparison, and (slow) every study's quick form reproduces the findings its
committed report-quick.md states."""
import math

import pytest

from bifurc.commands.study import check_study, committed_report, load_study, studies
from bifurc.findings import Finding, compare, parse, table


def test_a_findings_table_reads_back_and_a_moved_finding_fails():
    stated = [Finding("hammering cells", 12, 1, "cells"), Finding("class at 4 Hz", "period-1, no impact"),
              Finding("lowest voltage", 137.5, 6.875, "V"), Finding("none found", math.nan, 1, "V")]
    form, back = parse("# report\n\ntext\n\n" + table(stated, "quick", "bifurc study x --quick -o DIR"))
    assert form == "quick" and list(back) == [f.name for f in stated]
    assert back["lowest voltage"].value == 137.5 and back["lowest voltage"].tolerance == 6.875
    assert compare(back, stated) == []
    moved = [Finding("hammering cells", 14, 1, "cells"), Finding("class at 4 Hz", "chaotic"),
             Finding("lowest voltage", 144.0, 6.875, "V"), Finding("none found", 50.0, 1, "V")]
    bad = compare(back, moved)
    assert len(bad) == 3 and all(b.split(":")[0] in ("hammering cells", "class at 4 Hz", "none found") for b in bad)
    assert compare(back, stated[:2] + stated[3:]) == ["lowest voltage: stated 137.5 V, no longer reported"]


STATED = [name for name in studies() if hasattr(load_study(name), "findings")
          and committed_report(load_study(name), True).is_file()]


@pytest.mark.slow
@pytest.mark.parametrize("name", STATED)
def test_every_quick_form_reproduces_its_committed_findings(name, tmp_path):
    assert check_study(name, tmp_path / "out", quick=True, progress=False) == []


def test_the_studies_with_findings_commit_their_quick_report():
    assert {"regime-maps", "thesis-1dof-relay"} <= set(STATED)


REPORT = """# demo: a study

Text.

## Findings (checked by `bifurc study NAME --check`)

Made by `bifurc study demo -o DIR` at git abc1234 on 2026-11-26 05:00 UTC. Form: full. A number holds ...

| finding | value | tolerance | unit |
|---|---|---|---|
| cells that hammer | 12 | 1 | cells |
| class at 4 Hz | chaotic | exact |  |
"""


def test_the_findings_page_lists_every_stated_finding_and_catches_a_stale_one(tmp_path):
    from pathlib import Path

    from bifurc.findings import BEGIN, END, main
    root = tmp_path / "studies"
    for name, files in {"demo_a": {"report.md": REPORT}, "demo_b": {"report-quick.md": "# demo-b: not run yet\n"}}.items():
        (root / name).mkdir(parents=True)
        (root / name / "__init__.py").write_text("")
        for file, text in files.items():
            (root / name / file).write_text(text)
    page = tmp_path / "findings.md"
    page.write_text(f"# top\n\n{BEGIN}\nold text\n{END}\n\n## after\n")
    assert main(["--page", str(page), "--studies", str(root), "--check"]) == 1
    assert main(["--page", str(page), "--studies", str(root)]) == 0
    text = page.read_text()
    assert text.startswith("# top\n") and text.endswith(f"{END}\n\n## after\n") and "old text" not in text
    assert ("| demo-a | full | 2 | `bifurc study demo -o DIR`, git abc1234, 2026-11-26 05:00 UTC | "
            "studies/demo_a/report.md |") in text
    assert "| cells that hammer | 12 | 1 | cells |" in text and "| class at 4 Hz | chaotic | exact |  |" in text
    assert "- studies/demo_b/report-quick.md: demo-b: not run yet" in text
    assert main(["--page", str(page), "--studies", str(root), "--check"]) == 0
    page.write_text(text.replace("| 12 | 1 |", "| 13 | 1 |"))
    assert main(["--page", str(page), "--studies", str(root), "--check"]) == 1
    assert main(["--readme", str(page), "--studies", str(root), "--check"]) == 1   # the option's old name checks alike
    # the documentation's findings page holds the section its studies' reports give
    repo = Path(__file__).resolve().parents[1]
    assert main(["--page", str(repo / "docs" / "findings.md"), "--studies", str(repo / "studies"), "--check"]) == 0
    assert BEGIN not in (repo / "README.md").read_text()
