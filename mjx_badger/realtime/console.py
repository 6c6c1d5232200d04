"""The operator console: a web page and a WebSocket, served by the training process from a thread of its own.

The page (console.html, shipped in the package) shows the operator's state and buttons, the live numbers and their
plots, and drives a trained policy in test mode. The server pushes the operator's snapshot at most PUSH_HZ times a
second and takes button presses; it runs its own asyncio event loop in a daemon thread so that the control loop
never waits for it. On a loopback address it needs no token; served beyond it, every control message must carry the
token printed at start (`needs_token`), and a message without it is refused and never reaches the operator.
"""

import asyncio
import hmac
import ipaddress
import json
import logging
import math
import secrets
import socket
import sys
import threading
from importlib import resources
from urllib.parse import urlencode, urlsplit

from aiohttp import WSCloseCode, WSMsgType, web

from mjx_badger.realtime.operator import BUTTONS, MAX_COMMAND, STATES, Operator

log = logging.getLogger("mjx_badger.console")

PUSH_HZ = 5.0
"""The most snapshots a second the console sends each page: plenty for a person, nothing for the control loop."""
MAX_MESSAGE = 64 * 1024
"""The largest message a page may send (a press is a hundred bytes); a larger one closes its connection."""
SEND_TIMEOUT_S = 2.0
"""A page that takes longer to accept a snapshot (or to answer a close) is dropped: a stalled browser holds up none."""


def needs_token(host: str) -> bool:
    """Whether a console bound to `host` is reachable beyond this machine, so that control needs a token."""
    if host == "localhost":
        return False
    try:
        return not ipaddress.ip_address(host.strip("[]")).is_loopback
    except ValueError:  # a host name (or "" for every interface): it may resolve to anything
        return True


def resolve_token(host: str, token: str | None) -> str | None:
    """The token a console on `host` uses: the one given, a fresh one beyond loopback, else none."""
    if token is not None:
        return token
    return secrets.token_urlsafe(16) if needs_token(host) else None


def token_matches(sent, token: str) -> bool:
    """Whether a message's token is the console's; compared in constant time, so timing does not leak it."""
    return isinstance(sent, str) and hmac.compare_digest(sent.encode(), token.encode())


def dumps(message: dict) -> str:
    """JSON a browser parses: NaN and infinities (which JSON lacks) become null, NumPy scalars plain numbers."""
    try:
        return json.dumps(message, allow_nan=False, default=_plain)
    except ValueError:
        return json.dumps(_finite(message), default=_plain)


def _plain(value):
    return value.item() if hasattr(value, "item") else str(value)


def _finite(value):
    if isinstance(value, float):
        return value if math.isfinite(value) else None
    if isinstance(value, dict):
        return {k: _finite(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [_finite(v) for v in value]
    return value


def _refused(error: str) -> dict:
    return {"type": "reply", "ok": False, "error": error}


class Console:
    """A running console: its `url` (with ?token= when it has one), its `token`, and `stop()`."""

    def __init__(self, operator: Operator, host: str, port: int, token: str | None):
        self.operator, self.host, self.token = operator, host, token
        self.port = port
        self._html = resources.files(__package__).joinpath("console.html").read_text(encoding="utf-8")
        self._clients: set[web.WebSocketResponse] = set()
        self._last_sent = None
        self._loop: asyncio.AbstractEventLoop | None = None
        self._thread = threading.Thread(target=self._serve, name="operator-console", daemon=True)
        self._ready = threading.Event()
        self._failed: BaseException | None = None
        self._runner: web.AppRunner | None = None
        self._pusher: asyncio.Task | None = None

    @property
    def url(self) -> str:
        host = socket.gethostname() if self.host in ("", "0.0.0.0", "::") else self.host  # every interface
        host = f"[{host}]" if ":" in host else host
        query = f"?{urlencode({'token': self.token})}" if self.token is not None else ""
        return f"http://{host}:{self.port}/{query}"

    def start(self) -> "Console":
        self._thread.start()
        self._ready.wait()
        if self._failed is not None:
            raise self._failed
        return self

    def stop(self) -> None:
        """Close every page's connection and the server, and end the thread; a second call does nothing."""
        if not self._thread.is_alive():
            return
        asyncio.run_coroutine_threadsafe(self._close(), self._loop).result(timeout=10)
        self._loop.call_soon_threadsafe(self._loop.stop)
        self._thread.join(timeout=10)

    def __enter__(self) -> "Console":
        return self

    def __exit__(self, *_) -> None:
        self.stop()

    def _serve(self) -> None:
        self._loop = asyncio.new_event_loop()
        asyncio.set_event_loop(self._loop)
        try:
            self._loop.run_until_complete(self._open())
        except BaseException as error:  # handed to start(), which raises it in the caller's thread
            self._failed = error
            self._ready.set()
            self._loop.close()
            return
        self._ready.set()
        try:
            self._loop.run_forever()
        finally:
            self._loop.close()

    async def _open(self) -> None:
        app = web.Application()
        app.add_routes([web.get("/", self._page), web.get("/ws", self._socket)])
        self._runner = web.AppRunner(app, access_log=None)
        await self._runner.setup()
        try:
            await web.TCPSite(self._runner, self.host or None, self.port).start()
        except BaseException:
            await self._runner.cleanup()
            raise
        self.port = self._runner.addresses[0][1]
        self._pusher = asyncio.create_task(self._push_forever())

    async def _close(self) -> None:
        self._pusher.cancel()
        await asyncio.gather(*(page.close(code=WSCloseCode.GOING_AWAY, message=b"console stopped")
                               for page in list(self._clients)))
        await self._runner.cleanup()

    async def _page(self, request: web.Request) -> web.Response:
        return web.Response(text=self._html, content_type="text/html", headers={"Cache-Control": "no-store"})

    def _handshake_refused(self, request: web.Request) -> str | None:
        """Why a WebSocket may not open: another site's page in the browser, or (tokenless) a Host not this machine."""
        # WebSockets are not bound by the same-origin rule: without these checks any web site the operator's browser
        # opens could press this console's buttons, directly or through a DNS name of its own that points here.
        origin = request.headers.get("Origin")
        if origin is not None and urlsplit(origin).netloc != request.host:
            return f"a page from {origin} may not connect to this console"
        if self.token is None and needs_token(urlsplit(f"//{request.host}").hostname or ""):
            return f"this console serves this machine only, not {request.host}"
        return None

    async def _socket(self, request: web.Request) -> web.WebSocketResponse:
        refused = self._handshake_refused(request)
        if refused is not None:
            log.warning("refused a connection from %s: %s", request.remote, refused)
            raise web.HTTPForbidden(text=refused)
        page = web.WebSocketResponse(heartbeat=10.0, max_msg_size=MAX_MESSAGE, timeout=SEND_TIMEOUT_S)
        await page.prepare(request)
        await page.send_str(dumps(self._hello()))
        self._clients.add(page)
        try:
            async for message in page:
                if message.type == WSMsgType.TEXT:
                    reply = self._reply(message.data, request.remote)
                elif message.type == WSMsgType.BINARY:
                    reply = self._refuse(request.remote, "a message is JSON text, not binary")
                else:
                    break
                await page.send_str(dumps(reply))
        finally:
            self._clients.discard(page)
        return page

    def _hello(self) -> dict:
        """The first message: what the buttons may do, the limits of a command, and the history for the plots."""
        return {"type": "hello", "buttons": {b: list(allowed) for b, (allowed, _) in BUTTONS.items()},
                "states": list(STATES), "max_command": list(MAX_COMMAND), "push_hz": PUSH_HZ,
                "token_required": self.token is not None, "test_refusal": self.operator.test_refusal,
                "history": list(self.operator.history.copy()),
                "snapshot": self.operator.snapshot()}

    def _refuse(self, peer, error: str) -> dict:
        log.warning("refused a message from %s: %s", peer, error)
        return _refused(error)

    def _reply(self, data: str, peer) -> dict:
        """A page's message handled: a press passed to the operator, or why it was refused."""
        try:
            message = json.loads(data)
        except (ValueError, RecursionError):
            return self._refuse(peer, "a message is JSON")
        if not isinstance(message, dict):
            return self._refuse(peer, "a message is a JSON object")
        if message.get("type") != "press":
            return self._refuse(peer, f"unknown message type {str(message.get('type'))[:40]!r}; valid: press")
        if self.token is not None and not token_matches(message.get("token"), self.token):
            how = "without the" if message.get("token") is None else "with a wrong"
            return self._refuse(peer, f"a control message {how} token (the console printed its URL with the token "
                                      "at start)")
        button = message.get("button")
        if not isinstance(button, str):
            return self._refuse(peer, f"button is one of {', '.join([*BUTTONS, 'drive'])}")
        error = self.operator.press(button, message.get("command"))
        return {"type": "reply", "ok": error is None, "error": error, "state": self.operator.state,
                "command": list(self.operator.command)}

    async def _push_forever(self) -> None:
        while True:
            await asyncio.sleep(1.0 / PUSH_HZ)
            await self._push()

    async def _push(self) -> None:
        """The operator's snapshot to every page, when it changed since the last one sent."""
        if not self._clients:
            return
        snapshot = self.operator.snapshot()
        if snapshot == self._last_sent:
            return
        self._last_sent = snapshot
        text = dumps({"type": "snapshot", **snapshot})
        await asyncio.gather(*(self._send(page, text) for page in list(self._clients)))

    async def _send(self, page: web.WebSocketResponse, text: str) -> None:
        try:
            await asyncio.wait_for(page.send_str(text), SEND_TIMEOUT_S)
        except (ConnectionError, asyncio.TimeoutError, RuntimeError) as error:
            log.info("dropped a page that did not take a snapshot: %r", error)
            self._clients.discard(page)
            await page.close()


def serve(operator: Operator, host: str = "127.0.0.1", port: int = 0, token: str | None = None) -> Console:
    """Serve `operator`'s console on host:port (0: any free one) from a thread; beyond loopback with a token."""
    console = Console(operator, host, port, resolve_token(host, token)).start()
    note = " (control needs the token in this URL)" if console.token is not None else ""
    print(f"operator console: {console.url}{note}", file=sys.stderr, flush=True)
    log.info("operator console on %s:%d", host, console.port)
    return console
