"""Every result docs/ prints is what the code prints now: scripts/doc_results.py reruns each marked block, and a
block that differs fails here. The mazelog sessions take seconds (fast suite); the campaigns minutes (slow)."""

import importlib.util
import sys

import pytest

from tests.helpers.paths import SCRIPTS

SCRIPT = SCRIPTS / "doc_results.py"


def load():
    spec = importlib.util.spec_from_file_location("doc_results", SCRIPT)
    module = importlib.util.module_from_spec(spec)
    sys.modules["doc_results"] = module
    spec.loader.exec_module(module)
    return module


doc_results = load()


def drifts(wanted) -> list[str]:
    found, outputs = [], {}
    for doc in doc_results.DOCS:
        _, drift = doc_results.refresh((doc_results.REPO / doc).read_text(), doc, wanted, outputs)
        found += [f"{d.doc}: {d.name}:\n--- the doc\n{d.old}--- the code\n{d.new}" for d in drift]
    return found


def test_every_doc_session_prints_what_it_says():
    assert drifts(doc_results.chooser((), expensive=False)) == []


@pytest.mark.slow
def test_every_doc_campaign_result_is_what_the_campaign_gives():
    assert drifts(lambda name: name != doc_results.CONSOLE) == []


def test_a_drifted_figure_is_caught_and_rewritten_and_a_wall_time_is_not():
    doc = ("text\n<!-- doc-results: console -->\n```console\n$ echo 3; echo 'took in 0.25 s'\n4\ntook in 0.10 s\n"
           "```\n<!-- /doc-results -->\nmore text\n")
    new, found = doc_results.refresh(doc, "x.md", doc_results.chooser((), False), {})
    assert [d.name for d in found] == ["console"]
    assert new == doc.replace("\n4\n", "\n3\n")  # the figure follows the code; the wall time stays the doc's
    again, found = doc_results.refresh(new, "x.md", doc_results.chooser((), False), {})
    assert again == new and found == []


def test_a_view_in_a_table_cell_or_a_toml_comment_is_rewritten_in_place():
    out = ("best: [Kp=3.633, Ki=0.000, Kd=0.000] lap 32.57 s (set 23)\nsets: 25, tests: 75 (75 this run)\n"
           "validation on 30 fresh noise draws: 30/30 reached GOAL (success 1.00), lap p50 32.90 s, p90 33.38 s "
           "(the campaign's estimate: 32.57 s)\n")
    cell = "| a | <!-- doc-results: validate-example-row -->old<!-- /doc-results -->; 138 s | cmd |\n"
    new, _ = doc_results.refresh(cell, "x.md", lambda name: True, {"validate-example": out})
    assert new == ("| a | <!-- doc-results: validate-example-row -->best Kp 3.633, Ki 0, Kd 0 (set 23), campaign "
                   "estimate 32.57 s; on 30 fresh draws 30/30 GOAL, p50 32.90 s, p90 33.38 s<!-- /doc-results -->; "
                   "138 s | cmd |\n")
    comment = "# doc-results: validate-example-comment\n# old\n# /doc-results\n"
    new, _ = doc_results.refresh(comment, "x.toml", lambda name: True, {"validate-example": out})
    assert new.splitlines()[1].startswith(
        "# `hako run --trials 20 --validate 30` now finds Kp 3.633, Ki 0, Kd 0: lap 32.57 s")


def test_an_unknown_block_name_is_one_line():
    import click

    with pytest.raises(click.ClickException, match="unknown result 'nonsense'"):
        doc_results.refresh("<!-- doc-results: nonsense -->x<!-- /doc-results -->", "x.md", lambda n: True, {})
