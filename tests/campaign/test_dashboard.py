"""`hako dashboard RUN_DIR...`: optuna-dashboard on several campaigns, live, with their trajectories; bad input
is one line; and, in headless Chromium, the page a person sees."""

from __future__ import annotations

import dataclasses
import importlib.util
import json
import re
import shutil
import socket
import subprocess
import sys
import tempfile
import urllib.request
from collections.abc import Iterator
from pathlib import Path

import pytest

from testctl.campaign.loop import Campaign
from testctl.campaign.study import STUDY_FILE, StudyMirror
from tests.campaign.test_study import CONFIG, Drawer
from tests.helpers.campaign_doubles import SyntheticBench
from tests.helpers.commands import hako, one_line_error
from tests.helpers.paths import REPO
from tests.helpers.waiting import wait_until

pytestmark = pytest.mark.skipif(importlib.util.find_spec("optuna_dashboard") is None,
                                reason="needs optuna-dashboard (pip install -e '.[dashboard]')")
CHROMIUM, CHROMEDRIVER = shutil.which("chromium"), shutil.which("chromedriver")


def campaign(out: Path, trials: int = CONFIG.trials, seed: int = CONFIG.seed, *, resume: bool = False) -> None:
    config = dataclasses.replace(CONFIG, trials=trials, seed=seed)
    Campaign(config, out, SyntheticBench(), on_sets=StudyMirror(out, Drawer()).update, resume=resume).run()


class Dashboard:
    """`hako dashboard` in a process of its own on a free port, until the test ends."""

    def __init__(self, *run_dirs: Path) -> None:
        self.proc = subprocess.Popen([sys.executable, "-m", "testctl.hako", "dashboard", *map(str, run_dirs),
                                      "--port", "0"], stderr=subprocess.PIPE, text=True, cwd=REPO)
        line = self.proc.stderr.readline()
        found = re.search(r"http://127\.0\.0\.1:(\d+)/dashboard", line)
        assert found, line + self.proc.stderr.read()
        self.url = f"http://127.0.0.1:{found.group(1)}"

    def get(self, path: str) -> bytes:
        with urllib.request.urlopen(self.url + path, timeout=30) as r:
            return r.read()

    def json(self, path: str) -> dict:
        return json.loads(self.get(path))

    def close(self) -> None:
        self.proc.terminate()
        self.proc.wait(timeout=30)
        self.proc.stderr.close()


@pytest.fixture
def dashboard() -> Iterator[callable]:
    opened: list[Dashboard] = []

    def start(*run_dirs: Path) -> Dashboard:
        opened.append(Dashboard(*run_dirs))
        return opened[-1]

    yield start
    for d in opened:
        d.close()


def studies(d: Dashboard) -> dict[str, dict]:
    """{study name: its detail} as the dashboard's API gives them."""
    return {s["study_name"]: d.json(f"/api/studies/{s['study_id']}") for s in d.json("/api/studies")["study_summaries"]}


def test_two_campaigns_side_by_side_with_their_trajectories(tmp_path: Path, dashboard) -> None:
    campaign(tmp_path / "a")
    campaign(tmp_path / "b", trials=1, seed=10)
    d = dashboard(tmp_path / "a", tmp_path / "b")
    shown = studies(d)
    assert sorted(shown) == ["a", "b"]
    assert [len(shown[n]["trials"]) for n in ("a", "b")] == [6, 4]
    ids = {s["study_name"]: s["study_id"] for s in d.json("/api/studies")["study_summaries"]}
    for name, detail in shown.items():
        with_files = [t for t in detail["trials"] if t["artifacts"]]
        assert with_files, name  # the sets that improved on the best carry their trajectory
        for t in with_files:
            (meta,) = t["artifacts"]
            body = d.get(f"/artifacts/{ids[name]}/{t['trial_id']}/{meta['artifact_id']}")
            assert body == f"trajectory of set {t['number'] + 1}".encode()
        attrs = {a["key"]: a["value"] for a in detail["trials"][0]["user_attrs"]}
        assert attrs["set"] == "1" and json.loads(attrs["tests"])[0]["rep"] == 1


def test_campaigns_of_one_name_are_told_apart(tmp_path: Path, dashboard) -> None:
    campaign(tmp_path / "x" / "c")
    campaign(tmp_path / "y" / "c", seed=12)
    names = sorted(studies(dashboard(tmp_path / "x" / "c", tmp_path / "y" / "c")))
    assert names == [f"c ({tmp_path / 'x' / 'c'})", f"c ({tmp_path / 'y' / 'c'})"]


def test_the_page_follows_a_running_campaign(tmp_path: Path, dashboard) -> None:
    campaign(tmp_path / "a", trials=1)
    d = dashboard(tmp_path / "a")
    assert len(studies(d)["a"]["trials"]) == 4
    campaign(tmp_path / "a", trials=3, resume=True)  # two more sets, appended while the dashboard serves
    # optuna-dashboard caches a small study's trials for 2 s
    wait_until(lambda: len(studies(d)["a"]["trials"]) == 6, 30, 0.5, what="the two sets on the dashboard")


def test_bad_input_is_one_line(tmp_path: Path) -> None:
    one_line_error(hako("dashboard", str(tmp_path / "missing")), "no such folder")
    one_line_error(hako("dashboard", str(tmp_path)), "is no campaign", "journal.jsonl")
    campaign(tmp_path / "a")
    (tmp_path / "a" / STUDY_FILE).unlink()
    one_line_error(hako("dashboard", str(tmp_path / "a")), "no optuna.log", "hako run --resume")
    campaign(tmp_path / "b")
    with socket.socket() as taken:
        taken.bind(("127.0.0.1", 0))
        taken.listen()
        port = taken.getsockname()[1]
        one_line_error(hako("dashboard", str(tmp_path / "b"), "--port", str(port)), f"127.0.0.1:{port}",
                       "in use", "--port")
    assert hako("dashboard", "-h").returncode == 0


def test_without_optuna_dashboard_one_line_says_what_to_install(tmp_path: Path, monkeypatch) -> None:
    from click.testing import CliRunner

    from testctl.hako.main import main

    campaign(tmp_path / "a")
    real = importlib.util.find_spec
    monkeypatch.setattr(importlib.util, "find_spec",
                        lambda name, *a: None if name == "optuna_dashboard" else real(name, *a))
    r = CliRunner().invoke(main, ["dashboard", str(tmp_path / "a")])
    assert r.exit_code == 1 and r.output.strip().splitlines() == [
        "Error: hako dashboard needs optuna-dashboard, which is not installed: pip install -e '.[dashboard]' "
        "(or pip install optuna-dashboard)"]


def _chrome_driver(user_data: Path):
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service

    options = webdriver.ChromeOptions()
    options.binary_location = CHROMIUM
    for flag in ("--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
                 "--disable-background-networking", "--disable-component-update", "--disable-sync",
                 f"--user-data-dir={user_data}", "--window-size=1400,1000"):
        options.add_argument(flag)
    return webdriver.Chrome(service=Service(CHROMEDRIVER), options=options)


@pytest.mark.slow
@pytest.mark.skipif(CHROMIUM is None or CHROMEDRIVER is None,
                    reason="needs Debian's chromium and chromium-driver (apt-get install chromium chromium-driver; "
                           ".ci/run installs them)")
@pytest.mark.skipif(importlib.util.find_spec("selenium") is None, reason="needs selenium (pip install -e '.[test]')")
def test_a_smoke_campaign_in_a_real_browser(tmp_path: Path, dashboard) -> None:
    """What a person sees: `hako run --smoke`, then `hako dashboard` in headless Chromium: the study, its trial
    count, a trial's tests and its trajectory artifact. Screenshots are kept in the test's folder."""
    from selenium.webdriver.common.by import By
    from selenium.webdriver.support import expected_conditions as shown
    from selenium.webdriver.support.ui import WebDriverWait

    out = tmp_path / "s"
    r = hako("run", "--smoke", "--app", "line_trace_c", "--out", str(out))
    assert r.returncode == 0, r.stderr
    assert (out / STUDY_FILE).is_file()
    d = dashboard(out)
    browser = _chrome_driver(Path(tempfile.mkdtemp(dir=tmp_path)))
    try:
        wait = WebDriverWait(browser, 60)
        browser.get(d.url + "/dashboard")
        wait.until(shown.text_to_be_present_in_element((By.TAG_NAME, "body"), "s"))
        wait.until(lambda b: "MINIMIZE" in b.find_element(By.TAG_NAME, "body").text)
        browser.save_screenshot(str(tmp_path / "studies.png"))
        browser.get(d.url + "/dashboard/studies/0/trials")
        wait.until(shown.text_to_be_present_in_element((By.TAG_NAME, "body"), "4 Trials"))
        body = browser.find_element(By.TAG_NAME, "body").text
        for words in ("Trial 0", "Trial 3", "lap_s", "Artifacts", "set-001.png"):
            assert words in body, body
        browser.save_screenshot(str(tmp_path / "trials.png"))
        images = [i for i in browser.find_elements(By.TAG_NAME, "img")
                  if "/artifacts/" in (i.get_attribute("src") or "")]
        assert images and all(browser.execute_script("return arguments[0].naturalWidth", i) > 100 for i in images)
    finally:
        browser.quit()
    print(f"screenshots: {tmp_path / 'studies.png'}, {tmp_path / 'trials.png'}")
