"""The operator console in a real browser: headless Chromium (Debian's chromium and chromium-driver) via Selenium.

Behind the page runs the on-robot loop on the simulated HB40: Learn advances the steps on the page, Collapse damps the
robot, and in test mode a committed policy walks it under the command sent from the page.
CONSOLE_SCREENSHOT=path saves the page during the test mode's drive (for docs/realtime/console.png).
"""

import os
import threading
from pathlib import Path
from typing import Callable, NamedTuple

import pytest

from mjx_badger.agents.config import ALGORITHMS
from mjx_badger.outputs import onnx_export
from mjx_badger.realtime import loop
from mjx_badger.realtime.config import RealtimeConfig
from mjx_badger.realtime.console import serve
from mjx_badger.realtime.onboard import OnboardPolicy
from mjx_badger.realtime.operator import Operator
from mjx_badger.realtime.simulated import SimulatedHB40

CHROMIUM, CHROMEDRIVER = Path("/usr/bin/chromium"), Path("/usr/bin/chromedriver")
_missing = [str(p) for p in (CHROMIUM, CHROMEDRIVER) if not p.exists()]
pytestmark = pytest.mark.skipif(bool(_missing), reason=f"no {' or '.join(_missing)}: install Debian's chromium and "
                                                       "chromium-driver (.ci/run does)")
WAIT_S = 30.0
"""How long the page may take to show a change: a few pushes, plus the velocity settling after a command."""
COMPILE_S = 300.0
"""How long the first steps may take: the loop compiles its programs first."""


class Run(NamedTuple):
    operator: Operator
    url: str
    stop: Callable[[], None]


# A run small enough for a test (a 32x32 CrossQ at 20 Hz) and long enough never to finish during one.
TINY = RealtimeConfig(approach="jt-oef", algo="crossq", steps=100_000, warmup_steps=20, control_hz=20.0,
                      eval_seconds=0.0, agent=ALGORITHMS["crossq"]().replace(hidden=(32, 32), batch_size=16))
TEST_POLICY = Path("figures/data/full/thesis-code/omni-random/jt-nf_crossq_omni-random.json")
"""The committed policy test mode walks with: JT-NF trained on random commands in every direction (full profile)."""


def start_run(out_dir: Path) -> Run:
    """The on-robot loop on the simulated HB40, idle until the console's buttons say otherwise, with a test policy
    exported from a committed run; a console serves it."""
    policy = OnboardPolicy(onnx_export.export(TEST_POLICY, None, out_dir / "policy.onnx"))
    operator, stopping = Operator(state="idle"), threading.Event()
    operator.test_refusal = None  # a trained policy walks the robot in test mode
    thread = threading.Thread(target=loop.run, daemon=True, args=(TINY, SimulatedHB40(reset_seconds=0.1), out_dir),
                              kwargs=dict(resume=False, view=False, operator=operator, test_policy=policy,
                                          stop=stopping))
    thread.start()
    console = serve(operator)

    def stop():
        console.stop()
        stopping.set()
        thread.join()
    return Run(operator, console.url, stop)


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    started = start_run(tmp_path_factory.mktemp("run"))
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


def _until(browser, condition, what: str = "", timeout_s: float = WAIT_S):
    from selenium.webdriver.support.ui import WebDriverWait
    WebDriverWait(browser, timeout_s, poll_frequency=0.1).until(lambda _: condition(), what or None)


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


def _measured_vx(browser) -> float:
    try:
        return float(_text(browser, "num-measured").split(",")[0])
    except ValueError:  # "–" before the first number
        return float("nan")


def _steps(browser) -> int:
    return int(_text(browser, "num-steps").split("/")[0])


def test_learn_advances_the_steps_and_collapse_damps_the_robot(page, run):
    from selenium.webdriver.common.by import By
    browser = page
    assert not browser.find_element(By.ID, "btn-learn").is_enabled()  # idle: stand up first
    _click(browser, "btn-stand_up", "standing")
    _click(browser, "btn-learn", "learning")
    _until(browser, lambda: _text(browser, "num-steps") != "–", "the first numbers", COMPILE_S)
    first = _steps(browser)
    # The loop compiles its programs before it takes the first step (a minute on a busy 2-core machine).
    _until(browser, lambda: _steps(browser) > first + 20, "the steps advancing", COMPILE_S)
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
    for command, followed in ((-0.3, lambda vx: vx < -0.15), (0.0, lambda vx: abs(vx) < 0.05)):
        vx = browser.find_element(By.ID, "cmd-vx")
        vx.clear()
        vx.send_keys(str(command))
        browser.find_element(By.ID, "btn-send").click()
        _until(browser, lambda: run.operator.command == (command, 0.0, 0.0), "the operator taking the command")
        _until(browser, lambda: _text(browser, "num-command") == f"{command:.2f}, 0.00, 0.00", "the page showing it")
        _until(browser, lambda: followed(_measured_vx(browser)), f"the robot's velocity following {command} m/s")
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
