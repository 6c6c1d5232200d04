"""The operator console in a real browser: headless Chromium (Debian's chromium and chromium-driver) via Selenium.

Learn advances the steps on the page, Collapse damps the robot, and test mode's command is followed. The run behind
the page comes from `start_run`, the one function to swap for the real loop on the simulated robot.
CONSOLE_SCREENSHOT=path saves the page during the test mode's drive (for docs/realtime/console.png).
"""

import os
import random
import threading
import time
from pathlib import Path
from typing import Callable, NamedTuple

import pytest

from mjx_badger.realtime.console import serve
from mjx_badger.realtime.operator import Operator

CHROMIUM, CHROMEDRIVER = Path("/usr/bin/chromium"), Path("/usr/bin/chromedriver")
_missing = [str(p) for p in (CHROMIUM, CHROMEDRIVER) if not p.exists()]
pytestmark = pytest.mark.skipif(bool(_missing), reason=f"no {' or '.join(_missing)}: install Debian's chromium and "
                                                       "chromium-driver (.ci/run does)")
WAIT_S = 20.0
"""How long the page may take to show a change: a few pushes, plus the velocity settling after a command."""
FOLLOWED_WITHIN = 0.03
"""How close (m/s) the robot's measured vx comes to the commanded one."""


class Run(NamedTuple):
    operator: Operator
    url: str
    stop: Callable[[], None]


def start_run() -> Run:
    """A stand-in for the loop: steps advance while learning, motors damped once collapsed, the velocity follows
    the test command; it publishes the loop's snapshot keys 5 times a second, and a console serves it."""
    operator, stopping = Operator(state="idle"), threading.Event()
    operator.test_refusal = None  # a trained policy walks the robot in test mode

    def run():
        step, falls, vx, noise = 0, 0, 0.0, random.Random(0)
        start = time.monotonic()
        while not stopping.wait(0.05):
            state = operator.state
            step += 20 if state == "learning" else 0
            target = {"learning": 0.25, "testing": operator.command[0]}.get(state, 0.0)
            vx += 0.25 * (target - vx)  # a first-order lag: the robot takes a second to reach a command
            if step and step % 2000 == 0:
                falls += 1
            if round((time.monotonic() - start) / 0.05) % 4 == 0:
                operator.publish({
                    "step": step, "steps": 20_000, "eta_s": (20_000 - step) / 400, "falls": falls,
                    "episodes": falls + 1,
                    "estimated_vx": vx + noise.gauss(0, 0.02), "true_vx": vx, "reward": vx * 4 - 0.1,
                    "period_p50_ms": 25.0 + noise.gauss(0, 0.1), "period_p99_ms": 26.5 + noise.gauss(0, 0.3),
                    "late": 0, "updates_per_s": 180.0 if state == "learning" else 0.0, "link": "in-process", "gaps": 0,
                    "damped": state == "collapsed", "true_command_vx": vx, "true_vy": 0.0, "true_yaw": 0.0})
    thread = threading.Thread(target=run, daemon=True)
    thread.start()
    console = serve(operator)

    def stop():
        console.stop()
        stopping.set()
        thread.join()
    return Run(operator, console.url, stop)


@pytest.fixture
def run():
    started = start_run()
    yield started
    started.stop()


@pytest.fixture(scope="module")
def browser(tmp_path_factory):
    webdriver = pytest.importorskip("selenium.webdriver", reason="selenium is not installed (the test extra pins it)")
    options = webdriver.ChromeOptions()
    options.binary_location = str(CHROMIUM)
    for flag in ("--headless", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage",
                 "--disable-background-networking", "--disable-component-update", "--disable-sync", "--no-first-run",
                 "--window-size=1400,1050", f"--user-data-dir={tmp_path_factory.mktemp('chromium')}"):
        options.add_argument(flag)
    options.set_capability("goog:loggingPrefs", {"browser": "ALL"})  # the page's JavaScript errors, for _open's check
    driver = webdriver.Chrome(service=webdriver.ChromeService(str(CHROMEDRIVER)), options=options)
    yield driver
    driver.quit()


@pytest.fixture
def page(browser, run):
    """The browser on the console of a fresh run; the page logged no error by the end of the test."""
    browser.get(run.url)
    _until(browser, lambda: _text(browser, "connection") == "connected")
    yield browser
    errors = [entry for entry in browser.get_log("browser") if entry["level"] == "SEVERE"]
    assert not errors, errors


def _until(browser, condition, what: str = ""):
    from selenium.webdriver.support.ui import WebDriverWait
    WebDriverWait(browser, WAIT_S, poll_frequency=0.1).until(lambda _: condition(), what or None)


def _text(browser, element_id: str) -> str:
    from selenium.webdriver.common.by import By
    return browser.find_element(By.ID, element_id).text


def _click(browser, element_id: str, state_after: str):
    """Click a button once it is enabled; the page's state badge then shows `state_after`."""
    from selenium.webdriver.common.by import By
    button = browser.find_element(By.ID, element_id)
    _until(browser, button.is_enabled, f"{element_id} enabled")
    button.click()
    _until(browser, lambda: browser.find_element(By.ID, "state").get_attribute("data-state") == state_after,
           f"the state badge showing {state_after}")


def _steps(browser) -> int:
    return int(_text(browser, "num-steps").split("/")[0])


def test_learn_advances_the_steps_and_collapse_damps_the_robot(page, run):
    from selenium.webdriver.common.by import By
    browser = page
    assert not browser.find_element(By.ID, "btn-learn").is_enabled()  # idle: stand up first
    _click(browser, "btn-stand_up", "standing")
    _click(browser, "btn-learn", "learning")
    _until(browser, lambda: _text(browser, "num-steps") != "–")
    first = _steps(browser)
    _until(browser, lambda: _steps(browser) > first, "the steps advancing")
    assert _text(browser, "num-damped") == "no"
    _click(browser, "btn-collapse", "collapsed")
    _until(browser, lambda: _text(browser, "num-damped") == "yes", "the page showing the motors damped")
    assert run.operator.state == "collapsed"
    assert not browser.find_element(By.ID, "btn-collapse").is_enabled()


def test_test_mode_drives_the_robot_with_the_command_sent(page, run):
    from selenium.webdriver.common.by import By
    browser = page
    _click(browser, "btn-stand_up", "standing")
    _click(browser, "btn-test", "testing")
    vx = browser.find_element(By.ID, "cmd-vx")
    vx.clear()
    vx.send_keys("0.3")
    browser.find_element(By.ID, "btn-send").click()
    _until(browser, lambda: run.operator.command == (0.3, 0.0, 0.0), "the operator taking the command")
    _until(browser, lambda: _text(browser, "num-command") == "0.30, 0.00, 0.00", "the page showing the command")
    _until(browser, lambda: abs(float(_text(browser, "num-measured").split(",")[0]) - 0.3) < FOLLOWED_WITHIN,
           "the robot's velocity following the command")
    assert _text(browser, "message") == "done"
    if os.environ.get("CONSOLE_SCREENSHOT"):
        browser.save_screenshot(os.environ["CONSOLE_SCREENSHOT"])


def test_without_its_token_the_page_is_read_only(browser):
    from selenium.webdriver.common.by import By
    operator = Operator(state="standing")
    with serve(operator, token="t") as console:
        browser.get(console.url.split("?")[0])
        _until(browser, lambda: "Read only" in _text(browser, "message"), "the page saying it is read only")
        assert not any(b.is_enabled() for b in browser.find_elements(By.CSS_SELECTOR, "button[data-button]"))
        browser.execute_script("socket.send(JSON.stringify({type: 'press', button: 'learn'}))")  # past the page
        _until(browser, lambda: "token" in _text(browser, "message") and "Read only" not in _text(browser, "message"))
        assert operator.state == "standing"
        browser.get(console.url)
        _click(browser, "btn-learn", "learning")
    assert operator.state == "learning"
