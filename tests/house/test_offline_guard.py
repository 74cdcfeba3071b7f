"""The test run is offline: pytest-socket (configured in pyproject.toml's addopts) refuses a
connection to any address but loopback, and lets loopback through (the real uvicorn test, the
test client's socketpair).

The refused target, 192.0.2.1, is TEST-NET-1 (RFC 5737): it is never routed. It is also
tried over UDP, where connect() sends no packet at all, so even a missing guard would put
nothing on the wire; the test would just fail.
"""
import socket
import threading
import warnings

import pytest
import pytest_socket


def _connect(family, kind, address):
    with warnings.catch_warnings():  # pytest-socket also warns with the message it raises
        warnings.simplefilter("ignore")
        with socket.socket(family, kind) as s:
            s.settimeout(2)
            s.connect(address)


@pytest.mark.parametrize("kind", [socket.SOCK_DGRAM, socket.SOCK_STREAM], ids=["udp", "tcp"])
def test_a_non_loopback_address_is_refused(kind):
    if kind == socket.SOCK_STREAM:
        # only once the guard has been seen to refuse without sending anything (UDP) is TCP tried
        with pytest.raises(pytest_socket.SocketConnectBlockedError):
            _connect(socket.AF_INET, socket.SOCK_DGRAM, ("192.0.2.1", 9))
    with pytest.raises((pytest_socket.SocketBlockedError, pytest_socket.SocketConnectBlockedError),
                       match="192.0.2.1"):
        _connect(socket.AF_INET, kind, ("192.0.2.1", 9))


def _echo_once(server):
    conn, _ = server.accept()
    with conn:
        conn.sendall(conn.recv(16))


@pytest.mark.parametrize("host", ["127.0.0.1", "localhost", "::1"])
def test_loopback_is_allowed(host):
    family = socket.AF_INET6 if ":" in host else socket.AF_INET
    bind = "::1" if family == socket.AF_INET6 else "127.0.0.1"
    with socket.socket(family, socket.SOCK_STREAM) as server:
        try:
            server.bind((bind, 0))
        except OSError:
            if family == socket.AF_INET:
                raise       # every machine has IPv4 loopback: failing to bind it is a real failure
            # a kernel or container without IPv6 has no ::1 to connect to; the IPv4 cases still run
            pytest.skip("this machine has no IPv6 loopback (::1 cannot be bound), so it cannot be tested here")
        server.listen(1)
        port = server.getsockname()[1]
        t = threading.Thread(target=_echo_once, args=(server,), daemon=True)
        t.start()
        with socket.create_connection((host, port), timeout=5) as c:
            c.sendall(b"ping")
            assert c.recv(16) == b"ping"
        t.join(5)


def test_socketpair_is_allowed():
    a, b = socket.socketpair()  # what an asyncio event loop (the test client's) opens first
    with a, b:
        a.sendall(b"x")
        assert b.recv(1) == b"x"
