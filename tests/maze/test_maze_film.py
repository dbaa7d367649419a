"""`replay --animate` (a GIF of a search) and `replay --format png`, whose pixels its last frame repeats."""

import io
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from PIL import Image

from maze.files.builtin import builtin_path
from maze.files.mazefile import parse_maze
from maze.log.wallrecord import WallRecord, encode_log
from maze.pictures.film import MAX_FRAMES, default_stride, write_gif
from maze.pictures.render import COLOURS, PALETTE
from maze.search.explorer import explore
from tests.helpers.commands import mazelog

CLASSIC = builtin_path("alljapan-010-1989-fin")


@pytest.fixture(scope="module")
def search_log(tmp_path_factory) -> tuple[Path, list[WallRecord]]:
    records = explore(parse_maze(CLASSIC.read_text()), "stop").records
    log = tmp_path_factory.mktemp("film") / "run.bin"
    log.write_bytes(encode_log(records))
    return log, records


def rgb(path: Path, frame: int | None = None) -> np.ndarray:
    im = Image.open(path)
    if frame is not None:
        im.seek(frame)
    return np.asarray(im.convert("RGB"))


def has_colour(pixels: np.ndarray, name: str) -> bool:
    return bool((pixels == COLOURS[name]).all(axis=2).any())


@pytest.mark.parametrize("stride", [1, 7])
def test_film_has_a_frame_per_stride_and_ends_on_the_replay_png(tmp_path, search_log, stride):
    log, records = search_log
    gif, png = tmp_path / "run.gif", tmp_path / "last.png"
    result = mazelog("replay", log, "--size", 16, "--animate", gif, "--stride", stride)
    assert result.exit_code == 0, result.output
    assert mazelog("replay", log, "--size", 16, "--format", "png", "--out", png).exit_code == 0
    frames = Image.open(gif).n_frames
    assert frames == 1 + -(-len(records) // stride)  # the empty maze, then every stride records and the last
    assert (rgb(gif, frames - 1) == rgb(png)).all()
    assert not (rgb(gif, 0) == rgb(png)).all()


def test_with_the_true_maze_the_film_marks_the_path_and_a_misread_wall(tmp_path, search_log):
    log, records = search_log
    misread = records[40]
    bad = records[:40] + [WallRecord(misread.x, misread.y, misread.d, not misread.wall)] + records[41:]
    bad_log = tmp_path / "misread.bin"
    bad_log.write_bytes(encode_log(bad))
    gif, png = tmp_path / "run.gif", tmp_path / "last.png"
    assert mazelog("replay", bad_log, "--maze", CLASSIC, "--animate", gif).exit_code == 0
    assert mazelog("replay", bad_log, "--maze", CLASSIC, "--format", "png", "--out", png).exit_code == 0
    last = rgb(png)
    frames = Image.open(gif).n_frames
    assert (rgb(gif, frames - 1) == last).all()
    assert has_colour(last, "trail") and has_colour(last, "wrong") and has_colour(last, "mouse")
    truthful = tmp_path / "truthful.png"
    mazelog("replay", log, "--maze", CLASSIC, "--format", "png", "--out", truthful)
    maze_area = rgb(truthful)[: -60]  # above the legend, whose swatch has the colour
    assert not has_colour(maze_area, "wrong")


def test_a_32x32_search_film_is_a_few_mb_at_the_default_stride(tmp_path):
    truth = builtin_path("japan2019hef")
    log, gif = tmp_path / "run.bin", tmp_path / "run.gif"
    assert mazelog("explore", truth, "--log", log).exit_code == 0
    records = log.stat().st_size // 2
    result = mazelog("replay", log, "--maze", truth, "--animate", gif)
    assert result.exit_code == 0, result.output
    stride = default_stride(records)
    assert f"one per {stride} records" in result.output
    assert Image.open(gif).n_frames <= MAX_FRAMES + 2 and gif.stat().st_size < 3_000_000


def test_animate_into_a_missing_folder_is_a_one_line_error(search_log):
    log, _ = search_log
    result = mazelog("replay", log, "--animate", "/nonexistent/dir/run.gif")
    assert result.exit_code != 0 and result.output.startswith("Error") and "Traceback" not in result.output


@settings(max_examples=30, deadline=None)
@given(st.lists(st.lists(st.integers(0, len(COLOURS) - 1), min_size=12, max_size=12), min_size=1, max_size=6))
def test_gif_writer_round_trips_any_frames(frames):
    """Deltas with transparent unchanged pixels decode to exactly the frames written."""
    images = []
    for values in frames:
        im = Image.frombytes("P", (4, 3), bytes(values))
        im.putpalette(PALETTE)
        images.append(im)
    buffer = io.BytesIO()
    assert write_gif(iter(images), buffer) == len(images)
    gif = Image.open(io.BytesIO(buffer.getvalue()))
    assert gif.n_frames == len(images)
    for k, im in enumerate(images):
        gif.seek(k)
        assert (np.asarray(gif.convert("RGB")) == np.asarray(im.convert("RGB"))).all(), k
