"""The link's keys: ZeroMQ CURVE (authenticated and encrypted), required where the link leaves the machine.

`make(folder)` writes a key folder: server.key and server.key_secret for the robot's computer, client.key and
client.key_secret for the learner's, and authorized/ holding the client's public key (the server accepts only
clients whose public key lies there). Copy the folder to both machines; keep the secret files secret.
"""

import ipaddress
import shutil
from pathlib import Path
from urllib.parse import urlsplit

import zmq
import zmq.auth
from zmq.auth.thread import ThreadAuthenticator


def make(folder: Path) -> Path:
    """A new key folder (refused if one is there, so keys in use are never overwritten)."""
    folder = Path(folder)
    if (folder / "server.key").exists():
        raise ValueError(f"{folder} already holds keys; choose another folder (keys in use are not overwritten)")
    folder.mkdir(parents=True, exist_ok=True)
    zmq.auth.create_certificates(folder, "server")
    zmq.auth.create_certificates(folder, "client")
    (folder / "authorized").mkdir(exist_ok=True)
    shutil.copy(folder / "client.key", folder / "authorized" / "client.key")
    return folder


def is_local(address: str) -> bool:
    """Whether a tcp:// or ipc:// address stays on this machine (loopback or a socket file)."""
    if address.startswith(("ipc://", "inproc://")):
        return True
    host = urlsplit(address).hostname or ""
    if host == "localhost":
        return True
    try:
        return ipaddress.ip_address(host).is_loopback
    except ValueError:
        return False


def check(address: str, keys: Path | None, role: str) -> None:
    """ValueError unless the address stays on this machine or `keys` holds a key folder."""
    if keys is None and not is_local(address):
        raise ValueError(f"{address} leaves this machine: the {role} needs --keys FOLDER (CURVE, made by "
                         "`python -m mjx_badger link-keys FOLDER`)")
    if keys is not None and not (Path(keys) / "server.key").exists():
        raise ValueError(f"{keys} holds no link keys (server.key); make them with `python -m mjx_badger link-keys`")


def secure_server(socket, context, address: str, keys: Path | None):
    """CURVE on the robot's socket when `keys` is given (refused beyond loopback without it); the authenticator to
    stop with the server, or None."""
    check(address, keys, "robot server")
    if keys is None:
        return None
    keys = Path(keys)
    authenticator = ThreadAuthenticator(context)
    authenticator.start()
    authenticator.configure_curve(domain="*", location=str(keys / "authorized"))
    public, secret = zmq.auth.load_certificate(keys / "server.key_secret")
    socket.curve_secretkey, socket.curve_publickey, socket.curve_server = secret, public, True
    return authenticator


def secure_client(socket, address: str, keys: Path | None) -> None:
    """CURVE on the learner's socket when `keys` is given; refused beyond loopback without it."""
    check(address, keys, "learner")
    if keys is None:
        return
    keys = Path(keys)
    public, secret = zmq.auth.load_certificate(keys / "client.key_secret")
    server_public, _ = zmq.auth.load_certificate(keys / "server.key")
    socket.curve_secretkey, socket.curve_publickey, socket.curve_serverkey = secret, public, server_public
