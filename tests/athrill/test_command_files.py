"""The cells of teams' command files: found as a person finds them, replaced with every other byte kept; the
`row` and `ini` parameter forms that name them, read back from what they write."""

from __future__ import annotations

import pytest
from hypothesis import example, given
from hypothesis import strategies as st

from athrill_sim.tuning.bindings import from_json, to_json
from athrill_sim.tuning.command_files import NUMBER, CellError, ini_cell, replace_cells, row_cell
from athrill_sim.tuning.forms.form import Binding
from athrill_sim.tuning.forms.ini import Ini
from athrill_sim.tuning.forms.row import Row

CSV = """# section,name,distance,speed,kp,ki,kd
LineTrace,S001,500.0,0,0.03,0.001,0.008
Turn,S002,90,30
LineTrace,S003,800.0,0,0.05,0.002,0.010\r
"""
ROWS = """LineTracer 6000 20 50 50 LEFT_EDGE 1.3 0 0.013 BLUE
  DistanceStraight\t300   40
"""
INI = """speed = 50
[pid]
kp = 0.8   ; proportional
ki: 0.01
[turn]
kp=2
"""


def test_a_csv_row_is_found_by_its_key_and_its_occurrence():
    assert row_cell(CSV, "c.csv", key="LineTrace", column=5).text == "0.03"
    cell = row_cell(CSV, "c.csv", key="LineTrace", column=7, occurrence=2)
    assert cell.text == "0.010" and CSV[cell.start:cell.end] == "0.010"
    assert cell.where == "c.csv line 4 (LineTrace, occurrence 2), column 7"


def test_a_row_is_found_by_its_line_number_and_whitespace_separates_fields_without_a_comma():
    assert row_cell(ROWS, "r.txt", line=1, column=7).text == "1.3"
    assert row_cell(ROWS, "r.txt", key="DistanceStraight", column=3).text == "40"
    assert row_cell(CSV, "c.csv", line=3, column=3).text == "90"


def test_a_quoted_or_padded_csv_cell_is_its_number_alone():
    text = 'Run, " 0.5 ",x\nRun,"1,5", 7 \n'
    assert row_cell(text, "q.csv", key="Run", column=2).text == "0.5"
    assert row_cell(text, "q.csv", key="Run", column=3, occurrence=2).text == "7"


def test_an_ini_key_is_found_in_its_section_and_its_comment_is_kept():
    cell = ini_cell(INI, "t.ini", section="pid", key="kp")
    assert cell.text == "0.8"
    assert replace_cells(INI, [(cell, "1.25")]) == INI.replace("kp = 0.8 ", "kp = 1.25 ")
    assert ini_cell(INI, "t.ini", section="pid", key="ki").text == "0.01"
    assert ini_cell(INI, "t.ini", section="turn", key="kp").text == "2"
    assert ini_cell(INI, "t.ini", key="speed").text == "50"


@pytest.mark.parametrize("find, message", [
    (lambda: row_cell(CSV, "c.csv", key="Arc", column=3), "c.csv: no line whose first field is Arc"),
    (lambda: row_cell(CSV, "c.csv", key="Turn", column=3, occurrence=2),
     "c.csv: occurrence 2 of Turn: the file has 1 such line"),
    (lambda: row_cell(CSV, "c.csv", key="Turn", column=9),
     "c.csv line 3 (Turn), column 9 is past the end of the row, which has 4 fields"),
    (lambda: row_cell(CSV, "c.csv", key="Turn", column=2), "c.csv line 3 (Turn), column 2 is 'S002', not a number"),
    (lambda: row_cell(ROWS, "r.txt", line=1, column=6), "r.txt line 1, column 6 is 'LEFT_EDGE', not a number"),
    (lambda: row_cell(CSV, "c.csv", line=9, column=1), "c.csv: line 9: the file has 4 lines"),
    (lambda: ini_cell(INI, "t.ini", section="pid", key="kd"), "t.ini: no key kd in section [pid]"),
    (lambda: ini_cell(INI, "t.ini", key="kp"), "t.ini: no key kp before the first section"),
    (lambda: ini_cell(INI, "t.ini", section="gains", key="kp"),
     "t.ini: no section [gains] (its sections: [pid], [turn])"),
])
def test_each_missing_or_bad_cell_is_one_line_naming_the_file_and_the_row(find, message):
    with pytest.raises(CellError) as e:
        find()
    assert str(e.value) == message


def test_two_parameters_on_one_cell_are_refused():
    cell = row_cell(CSV, "c.csv", key="Turn", column=4)
    with pytest.raises(CellError, match="c.csv line 3 \\(Turn\\), column 4: two parameters on one cell"):
        replace_cells(CSV, [(cell, "1"), (cell, "2")])


numbers = st.from_regex(NUMBER, fullmatch=True)
names = st.from_regex(r"[A-Za-z_][A-Za-z0-9_]{0,8}", fullmatch=True)
separators = st.sampled_from([",", ", ", " ,", "\t", " ", "  "])


@st.composite
def command_files(draw):
    """A command file of rows: a key, then numbers, with one separator kind per row and random line ends."""
    rows = []
    for _ in range(draw(st.integers(1, 6))):
        sep = draw(separators)
        cells = [draw(names), *draw(st.lists(numbers, min_size=1, max_size=6))]
        rows.append(sep.join(cells) + draw(st.sampled_from(["\n", "\r\n"])))
    return "".join(rows)


@given(command_files(), st.data(), numbers)
@example("K,1\n", None, "2.5")
def test_replacing_a_cell_keeps_every_other_byte_and_reads_back(text, data, new):
    lines = text.splitlines(keepends=True)
    line = data.draw(st.integers(1, len(lines))) if data is not None else 1
    row = lines[line - 1].rstrip("\r\n")
    width = len(row.split(",")) if "," in row else len(row.split())
    column = data.draw(st.integers(2, width)) if data is not None else 2
    cell = row_cell(text, "f", line=line, column=column)
    changed = replace_cells(text, [(cell, new)])
    assert changed[:cell.start] == text[:cell.start]
    assert changed[cell.start + len(new):] == text[cell.end:]
    assert row_cell(changed, "f", line=line, column=column).text == new


paths = st.from_regex(r"[a-z]{1,8}(/[a-z]{1,8}){0,2}\.(csv|txt|ini)", fullmatch=True)
rows = st.builds(lambda f, k, line, c, o: Row(f, k, None, c, o) if line is None else Row(f, None, line, c, 1),
                 paths, names, st.none() | st.integers(1, 99), st.integers(1, 20), st.integers(1, 5))
inis = st.builds(Ini, paths, names, st.none() | names)


@given(st.one_of(rows, inis), st.floats(-10, 10), st.floats(10, 20))
def test_a_row_or_ini_parameter_reads_back_from_its_space_table_and_its_bindings_json(form, low, high):
    assert type(form).parse("p", form.toml()) == form
    binding = Binding("p", form, 560, low, high)
    assert from_json(to_json((binding,))) == (binding,)
