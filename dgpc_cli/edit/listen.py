"""Where the page listens: ``--host`` and ``--port`` checked before the page's server starts.

viser tries port after port when a bind fails (an address that is not this machine's fails on
every port: it tries a thousand and then waits for ever). So the address is resolved and every
socket it needs bound here first, once: an address that cannot be bound is one line naming
``--host``; a port in use is one line naming ``--port``, or, where the command allows it
(``--next-free-port``), the next free port above it, said on stderr."""

from __future__ import annotations

import errno
import logging
import socket

from dgpc_cli.errors import DgpcError

log = logging.getLogger(__name__)

#: Ports tried above a taken ``--port`` with ``--next-free-port``, at most.
NEXT_PORTS = 100


def _bind_all(host: str, port: int) -> int:
    """Bind (and close) a listening socket on every address ``host`` resolves to, as the
    page's server does (with SO_REUSEADDR); the port bound (a free one for 0). Raises
    OSError from the bind, or DgpcError where ``host`` resolves to nothing."""
    try:
        infos = socket.getaddrinfo(host, port, type=socket.SOCK_STREAM,
                                   flags=socket.AI_PASSIVE)
    except (socket.gaierror, UnicodeError, ValueError) as err:
        reason = getattr(err, "strerror", None) or str(err)
        raise DgpcError(f"{host!r} is not an address the page can listen on ({reason})",
                        source="--host") from None
    bound = port
    for family, kind, proto, _, address in infos:
        with socket.socket(family, kind, proto) as s:
            s.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
            if family == socket.AF_INET6:
                s.setsockopt(socket.IPPROTO_IPV6, socket.IPV6_V6ONLY, 1)
            s.bind(address)
            bound = s.getsockname()[1]
    return bound


def listening_port(host: str, port: int, next_free: bool = False) -> int:
    """The port the page will listen on at ``host``: ``port`` itself where it can be bound
    (0: the system's choice is left to the server), else with ``next_free`` the first free
    one of the :data:`NEXT_PORTS` above it (a warning says which). DgpcError (one line) for
    an address that cannot be bound (``--host``) or a port in use (``--port``)."""
    try:
        _bind_all(host, port)
        return port
    except OSError as err:
        reason = err.strerror or str(err)
        if err.errno == errno.EADDRNOTAVAIL:
            raise DgpcError(f"{host} is not an address of this machine ({reason})",
                            source="--host") from None
        if err.errno == errno.EACCES:
            raise DgpcError(f"port {port} on {host} is not allowed to this user ({reason}); "
                            "give one above 1023, or 0 for a free one",
                            source="--port") from None
        if err.errno != errno.EADDRINUSE or port == 0:
            raise DgpcError(f"cannot listen on {host} port {port}: {reason}",
                            source="--host") from None
    if not next_free:
        raise DgpcError(f"port {port} on {host} is in use (by another page or program); give "
                        "another, 0 for a free one, or --next-free-port to take the next free "
                        "one", source="--port")
    for candidate in range(port + 1, min(port + NEXT_PORTS, 65535) + 1):
        try:
            _bind_all(host, candidate)
        except OSError:
            continue
        log.warning("edit: port %d on %s is in use; using %d", port, host, candidate)
        return candidate
    raise DgpcError(f"port {port} on {host} and the {NEXT_PORTS} above it are in use",
                    source="--port")


def check_bound(host: str, asked: int, got: int) -> None:
    """After the server started: DgpcError where it took another port than ``asked`` (taken
    between the check and the server's bind; viser moves on silently)."""
    if asked and got != asked:
        raise DgpcError(f"port {asked} on {host} was taken just now (the page would have "
                        f"moved to {got}); try again", source="--port")
