"""The operator console without a browser: a WebSocket client on 127.0.0.1 reads snapshots and presses buttons."""

import asyncio
import json
import logging
import math
import socket
import threading
import time

import aiohttp
import pytest

from mjx_badger.realtime.console import PUSH_HZ, Console, dumps, needs_token, resolve_token, serve
from mjx_badger.realtime.operator import BUTTONS, Operator


@pytest.fixture
def served():
    operator = Operator(state="idle")
    operator.test_refusal = None  # as with a saved policy to test
    with serve(operator) as console:
        yield operator, console


def _ws(console) -> str:
    return f"ws://127.0.0.1:{console.port}/ws"


async def _reply(ws) -> dict:
    while True:
        message = await ws.receive_json(timeout=5)
        if message["type"] == "reply":
            return message


def _exchange(console, *messages, headers=None) -> tuple[dict, list[dict]]:
    """Connect, read the first message, send each (an object as JSON, text or bytes as they are); the replies."""
    async def talk():
        async with aiohttp.ClientSession() as session, session.ws_connect(_ws(console), headers=headers) as ws:
            hello, replies = await ws.receive_json(timeout=5), []
            for message in messages:
                if isinstance(message, bytes):
                    await ws.send_bytes(message)
                elif isinstance(message, str):
                    await ws.send_str(message)
                else:
                    await ws.send_json(message)
                replies.append(await _reply(ws))
            return hello, replies
    return asyncio.run(talk())


def test_only_loopback_hosts_go_without_a_token():
    for host in ("127.0.0.1", "127.0.1.1", "::1", "[::1]", "localhost"):
        assert not needs_token(host), host
    for host in ("0.0.0.0", "", "::", "192.168.1.20", "10.0.0.5", "badger.local", "example.com"):
        assert needs_token(host), host


def test_beyond_loopback_a_token_is_generated_unless_one_is_given():
    first, second = resolve_token("0.0.0.0", None), resolve_token("0.0.0.0", None)
    assert isinstance(first, str) and len(first) >= 20 and first != second
    assert resolve_token("0.0.0.0", "mine") == "mine"
    assert resolve_token("127.0.0.1", None) is None and resolve_token("127.0.0.1", "t") == "t"


def test_the_url_names_the_host_to_browse_and_carries_the_token():
    assert Console(Operator(), "0.0.0.0", 8080, "a b").url == f"http://{socket.gethostname()}:8080/?token=a+b"
    assert Console(Operator(), "::1", 8080, None).url == "http://[::1]:8080/"


def test_the_page_is_served_and_the_first_message_holds_the_buttons_and_history(served):
    operator, console = served
    operator.publish({"step": 1, "steps": 100})
    operator.publish({"step": 2, "steps": 100, "reward": float("nan")})

    async def get():
        async with aiohttp.ClientSession() as session, session.get(console.url) as page:
            return page.status, await page.text()
    status, html = asyncio.run(get())
    assert status == 200 and 'id="state"' in html and 'id="btn-learn"' in html
    assert "http" not in html.split("<script")[1].replace("https:", "")  # nothing fetched from elsewhere
    hello, _ = _exchange(console)
    assert hello["type"] == "hello" and hello["token_required"] is False
    assert hello["buttons"] == {b: list(allowed) for b, (allowed, _) in BUTTONS.items()}
    assert [s["step"] for s in hello["history"]] == [1, 2] and hello["history"][1]["reward"] is None  # NaN: null
    assert hello["snapshot"]["state"] == "idle" and console.url == f"http://127.0.0.1:{console.port}/"


def test_snapshots_are_pushed_as_they_change_at_most_push_hz_a_second(served):
    operator, console = served
    publishing = threading.Event()

    def publish():
        step = 0
        while not publishing.is_set():
            step += 1
            operator.publish({"step": step, "steps": 10**6})
            time.sleep(0.002)

    async def listen(seconds: float) -> list[dict]:
        async with aiohttp.ClientSession() as session, session.ws_connect(_ws(console)) as ws:
            await ws.receive_json(timeout=5)
            got, end = [], time.monotonic() + seconds
            while (left := end - time.monotonic()) > 0:
                try:
                    got.append(await ws.receive_json(timeout=left))
                except asyncio.TimeoutError:
                    break
            return got
    publisher = threading.Thread(target=publish, daemon=True)
    publisher.start()
    try:
        got = asyncio.run(listen(1.5))
    finally:
        publishing.set()
        publisher.join()
    assert all(m["type"] == "snapshot" and m["state"] == "idle" for m in got)
    assert 3 <= len(got) <= math.ceil(1.5 * PUSH_HZ) + 1, len(got)
    assert [m["step"] for m in got] == sorted(m["step"] for m in got)


def test_a_press_reaches_the_operator_and_a_refused_one_says_why(served):
    operator, console = served
    _, replies = _exchange(console, {"type": "press", "button": "learn"}, {"type": "press", "button": "stand_up"},
                           {"type": "press", "button": "test"},
                           {"type": "press", "button": "drive", "command": [0.3, 0, -0.5]},
                           {"type": "press", "button": "drive", "command": [9, 0, 0]})
    assert not replies[0]["ok"] and "learn is not possible while idle" in replies[0]["error"]
    assert replies[1] == {"type": "reply", "ok": True, "error": None, "state": "standing", "command": [0, 0, 0]}
    assert replies[2]["ok"] and replies[3]["ok"] and replies[3]["command"] == [0.3, 0, -0.5]
    assert not replies[4]["ok"] and "within" in replies[4]["error"]
    assert operator.state == "testing" and operator.command == (0.3, 0.0, -0.5)


def test_with_a_token_every_control_message_without_it_is_refused(capsys, caplog):
    operator = Operator(state="idle")
    with serve(operator, token="t") as console:
        assert console.url == f"http://127.0.0.1:{console.port}/?token=t" and console.token == "t"
        assert console.url in capsys.readouterr().err  # printed at start
        with caplog.at_level(logging.WARNING, logger="mjx_badger.console"):
            hello, replies = _exchange(console, *({"type": "press", "button": "stand_up", **extra} for extra in (
                {}, {"token": "wrong"}, {"token": None}, {"token": 1}, {"token": "tt"}, {"token": "é"})))
            assert hello["token_required"] is True
            assert all(not r["ok"] and "token" in r["error"] for r in replies), replies
            assert operator.state == "idle" and operator.refused == 0  # the operator never saw them
            assert sum("token" in r.getMessage() for r in caplog.records) == len(replies)
            _, [done] = _exchange(console, {"type": "press", "button": "stand_up", "token": "t"})
        assert done["ok"] and operator.state == "standing"


def test_malformed_messages_are_refused_and_the_server_goes_on(served):
    operator, console = served
    _, replies = _exchange(console, "not json", "[1, 2]", "3", json.dumps({"type": "hack"}), json.dumps({"no": "type"}),
                           {"type": "press"}, {"type": "press", "button": {"a": 1}}, {"type": "press", "button": "fly"},
                           {"type": "press", "button": "drive", "command": "fast"}, "[" * 60_000, b"\x00\x01")
    assert all(r["type"] == "reply" and not r["ok"] and r["error"] for r in replies), replies
    assert "unknown message type 'hack'" in replies[3]["error"] and "unknown button 'fly'" in replies[7]["error"]
    assert operator.state == "idle"
    _, [done] = _exchange(console, {"type": "press", "button": "stand_up"})
    assert done["ok"] and operator.state == "standing"


def test_a_message_too_large_closes_only_its_own_connection(served):
    operator, console = served

    async def oversized():
        async with aiohttp.ClientSession() as session, session.ws_connect(_ws(console)) as ws:
            await ws.receive_json(timeout=5)
            await ws.send_str("x" * 100_000)
            return (await ws.receive(timeout=5)).type
    assert asyncio.run(oversized()) in (aiohttp.WSMsgType.CLOSE, aiohttp.WSMsgType.CLOSED, aiohttp.WSMsgType.CLOSING)
    _, [done] = _exchange(console, {"type": "press", "button": "collapse"})
    assert done["ok"] and operator.state == "collapsed"


def test_another_sites_page_and_a_rebound_host_name_may_not_connect(served):
    operator, console = served
    for headers in ({"Origin": "http://evil.example"}, {"Host": f"evil.example:{console.port}"}):
        with pytest.raises(aiohttp.WSServerHandshakeError) as refused:
            _exchange(console, headers=headers)
        assert refused.value.status == 403
    hello, _ = _exchange(console, headers={"Origin": f"http://127.0.0.1:{console.port}"})  # the page itself
    assert hello["type"] == "hello"


def test_a_port_in_use_is_an_error_of_serve_and_stop_closes_the_pages_and_ends_the_thread(served):
    operator, console = served
    with pytest.raises(OSError):
        serve(operator, port=console.port)

    async def stopped_while_open():
        async with aiohttp.ClientSession() as session, session.ws_connect(_ws(console)) as ws:
            await ws.receive_json(timeout=5)
            await asyncio.get_running_loop().run_in_executor(None, console.stop)
            return await ws.receive(timeout=5)
    closed = asyncio.run(stopped_while_open())
    assert closed.type == aiohttp.WSMsgType.CLOSE and closed.data == aiohttp.WSCloseCode.GOING_AWAY
    assert not console._thread.is_alive()
    console.stop()  # a second stop does nothing


def test_dumps_makes_json_a_browser_parses():
    np = pytest.importorskip("numpy")
    nan, inf = float("nan"), float("inf")
    text = dumps({"a": inf, "b": [np.float32(0.5), np.int64(3), (1.0, nan)], "c": {"d": -inf}})
    assert json.loads(text) == {"a": None, "b": [0.5, 3, [1.0, None]], "c": {"d": None}}
