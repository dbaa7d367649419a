"""mms's rules as the world applies them: what a wall query answers and reveals, how far a move goes, the
scorekeeping, the reset button. Small mazes drawn here, so each answer can be checked by eye."""

from maze.direction import EAST, NORTH
from maze.files.mazefile import parse_maze
from maze.log.wallrecord import WallRecord
from maze.mouse.mms import COMMANDS, parse_command
from maze.mouse.mmsworld import MmsWorld, effective_distance
from maze.timing.mouseparams import load_mouse

# 3x3: a corridor up the west column, then east along the top row to the goal in the north-east corner
CORRIDOR = """\
o---o---o---o
|         G |
o   o---o---o
|   |       |
o   o   o   o
| S |       |
o---o---o---o
"""


def world(text: str = CORRIDOR, **kw) -> MmsWorld:
    truth = parse_maze(text)
    return MmsWorld(truth, load_mouse(None, truth.size), **kw)


def say(w: MmsWorld, *lines: str) -> list[str | None]:
    return [w.handle(parse_command(line)) for line in lines]


def test_queries_at_the_start_and_what_they_reveal() -> None:
    w = world()
    assert say(w, "wallFront", "wallLeft", "wallRight", "wallBack") == ["false", "true", "true", "true"]
    assert w.records == []  # the start cell's walls are known before any search (contest rule)
    assert say(w, "wallFront 3") == ["false"]  # the north side of (0, 1): open
    assert w.records == [WallRecord(0, 1, NORTH, False)]
    assert say(w, "wallFront 3") == ["false"] and len(w.records) == 1  # a wall is logged the first time only


def test_a_move_goes_as_far_as_it_can_and_then_crashes() -> None:
    w = world()
    assert say(w, "moveForward 5") == ["crash"]
    assert (w.point, w.steps) == ((1, 5), 2)  # stopped in (0, 2) by the north outer wall
    assert w.stats.total_distance == 10 and w.stats.total_effective == effective_distance(10)
    assert say(w, "moveForward") == ["crash"]
    assert w.point == (1, 5) and w.stats.total_distance == 10  # a wall straight ahead: no move, no distance


def test_a_diagonal_heading_from_a_cell_centre_faces_a_post() -> None:
    w = world()
    assert say(w, "turnRight45", "wallFront", "moveForwardHalf") == ["ack", "true", "crash"]
    assert w.stats.total_turns == 1


def test_a_run_to_the_goal_is_scored_as_mms_scores_it() -> None:
    w = world()
    assert say(w, "getStat score", "getStat best-run-turns") == ["2000", "-1"]
    say(w, "moveForward 2", "turnRight", "moveForward 2")
    assert w.truth.goals == ((2, 2),) and w._cell() == (2, 2)
    # best run: 1 turn, effective distance of two 4-half-step moves = 3 + 3; score adds 0.1 x (6 + 1)
    assert say(w, "getStat best-run-turns", "getStat best-run-effective-distance", "getStat score") == [
        "1", "6", "7.7"]


def test_set_wall_is_belief_not_sensing() -> None:
    w = world()
    assert say(w, "setWall 1 1 e", "clearWall 1 1 e", "setColor 1 1 r", "setText 1 1 hi") == [None] * 4
    assert w.belief == [WallRecord(1, 1, EAST, True), WallRecord(1, 1, EAST, False)]
    assert w.records == [] and len(w.marks) == 2
    say(w, "setColor 9 9 r")
    assert w.warnings == ["setColor 9 9: outside the 3x3 maze (ignored, as mms does)"]


def test_reset_button_and_ack_reset() -> None:
    w = world(reset_at=(1,))
    assert say(w, "wasReset", "moveForward", "wasReset") == ["false", "ack", "true"]
    assert say(w, "ackReset", "wasReset") == ["ack", "false"]
    assert (w.point, w.heading, w.resets) == ((1, 1), NORTH, 1)
    say(w, "moveForward")
    assert w.stats.current_effective == 15 + 2  # mms's reset penalty goes to the next run


def test_half_steps_and_the_search_time_model() -> None:
    w = world()
    say(w, "moveForwardHalf", "moveForwardHalf", "turnRight", "turnRight", "moveForward")
    assert w.trace == [(0, 0), (0, 1), (0, 0)] and w.pivots == 1 and w.turns == 2
    assert w.search().seconds > 0


def test_the_world_answers_exactly_the_commands_mms_answers() -> None:
    samples = {"": "", "n": "", "xy": " 1 1", "xyd": " 1 1 n", "xyc": " 1 1 r", "xyt": " 1 1 hi", "stat": " score"}
    for name, (spec, answered) in COMMANDS.items():
        reply = world().handle(parse_command(name + samples[spec]))
        assert (reply is not None) == answered, name


def test_marks_as_they_were_at_each_record() -> None:
    from maze.mouse.marks import CLEAR_ALL, Mark, marks_at

    marks = [Mark(0, (1, 1), colour="r"), Mark(2, (1, 1), text="5"), Mark(3, CLEAR_ALL, colour=""),
             Mark(4, (2, 2), colour="G")]
    assert marks_at(marks, 0) == {(1, 1): ("r", "")}
    assert marks_at(marks, 2) == {(1, 1): ("r", "5")}
    assert marks_at(marks, 3) == {(1, 1): ("", "5")}
    assert marks_at(marks, 9) == {(1, 1): ("", "5"), (2, 2): ("G", "")}
