"""``shapegen edit`` as a user runs it: the address printed, a clean stop, clear refusals."""

import json
import os
import shlex
import signal
import socket
import struct
import subprocess
import sys
import time
import urllib.request

import pytest
from editor_stack import CGA_BUILDING, WAIT_BOUND_S, cga_package

COMMAND = [sys.executable, "-m", "shapegen", "edit"]


def start(*args, env=None):
    process = subprocess.Popen(
        [*COMMAND, *args], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env
    )
    line = process.stdout.readline()
    return process, line


def test_edit_serves_prints_its_address_and_stops_on_ctrl_c(stack_file):
    process, line = start(str(stack_file), "--port", "0", "--no-open", "--set", "offset=0.7")
    try:
        assert line.startswith("shapegen edit: http://127.0.0.1:"), line
        url = line.split()[2]
        with urllib.request.urlopen(url + "api/state", timeout=60) as response:
            state = json.load(response)
        assert state["verdict"]["stands"] is False  # --set is honoured
        assert {a["name"]: a["value"] for a in state["attrs"]}["offset"] == 0.7
    finally:
        process.send_signal(signal.SIGINT)
        _, err = process.communicate(timeout=30)
    assert process.returncode == 0
    assert err.strip().endswith("shapegen edit: stopped") and "Traceback" not in err


def test_edit_opens_a_rule_package_as_the_package(tmp_path):
    package = cga_package(tmp_path)
    env = {**os.environ, "SHAPEGEN_CACHE": str(tmp_path / "cache")}
    process, line = start(
        str(package), "--port", "0", "--no-open", "--set", "lib.height=9", env=env
    )
    try:
        assert f"({package}, start rule " in line, line  # what was opened, then what is read
        url = line.split()[2]
        with urllib.request.urlopen(url + "api/attrs.json", timeout=60) as response:
            exported = json.load(response)
        # the package is watched: exported anew (one more floor), the page has it
        cga_package(
            tmp_path, CGA_BUILDING.replace("extrude(lib.height)", "extrude(lib.height + 1)")
        )
        # polled as the page does (the bound ends a wait that would never end; it times nothing)
        deadline = time.monotonic() + WAIT_BOUND_S
        blocks = None
        while blocks != 10 and time.monotonic() < deadline:
            time.sleep(0.1)
            with urllib.request.urlopen(url + "api/state", timeout=60) as response:
                blocks = json.load(response)["grammar"]["blocks"]
        assert blocks == 10
    finally:
        process.send_signal(signal.SIGINT)
        process.communicate(timeout=30)
    # the exported line builds the package the user opened, not its start rule in the cache
    assert shlex.split(exported["command"]) == [
        "shapegen", "build", str(package.resolve()), "--set", "lib.height=9"
    ]  # fmt: skip


def test_the_exported_line_finds_the_imports_where_the_page_found_them(tmp_path):
    from editor_stack import CGA_BUILDING, CGA_LIB

    rule = tmp_path / "project" / "rules" / "building.cga"
    rule.parent.mkdir(parents=True)
    rule.write_text(CGA_BUILDING, encoding="utf-8")
    shared = tmp_path / "shared"  # lib.cga is found only through --rules-path
    shared.mkdir()
    (shared / "lib.cga").write_text(CGA_LIB, encoding="utf-8")
    process, line = start(str(rule), "--rules-path", str(shared), "--port", "0", "--no-open")
    try:
        url = line.split()[2]
        with urllib.request.urlopen(url + "api/attrs.json", timeout=60) as response:
            exported = json.load(response)
    finally:
        process.send_signal(signal.SIGINT)
        process.communicate(timeout=30)
    words = shlex.split(exported["command_every_attr"])
    assert words[3:5] == ["--rules-path", str(shared)]
    report = tmp_path / "report.json"
    done = subprocess.run(
        [sys.executable, "-m", "shapegen", *words[1:], "--report", str(report), "-q"],
        capture_output=True, text=True, timeout=120,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    assert json.loads(report.read_text(encoding="utf-8"))["blocks"] == 6


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["missing.grammar"], "no grammar file 'missing.grammar'"),
        (["{stack}", "--set", "ofset=0.3"], "did you mean 'offset'?"),
    ],
)
def test_bad_arguments_are_one_line_and_status_2(stack_file, args, message):
    args = [a.replace("{stack}", str(stack_file)) for a in args]
    done = subprocess.run(
        [*COMMAND, *args, "--no-open"], capture_output=True, text=True, timeout=60
    )
    assert done.returncode == 2
    assert message in done.stderr and "Traceback" not in done.stderr


def test_a_port_in_use_is_refused_with_one_line(stack_file):
    with socket.socket() as taken:
        taken.bind(("127.0.0.1", 0))
        taken.listen()
        port = taken.getsockname()[1]
        done = subprocess.run(
            [*COMMAND, str(stack_file), "--port", str(port), "--no-open"],
            capture_output=True, text=True, timeout=60,
        )  # fmt: skip
    assert done.returncode == 2
    assert f"port {port} on 127.0.0.1 is in use" in done.stderr
    assert done.stderr.count("\n") == 1


def hang_up(port: int, data: bytes, *, reset: bool) -> None:
    """Connect, send ``data`` and leave: with a reset (RST, as a killed tab) or a plain close."""
    with socket.create_connection(("127.0.0.1", port), timeout=60) as client:
        client.sendall(data)
        if reset:
            client.setsockopt(socket.SOL_SOCKET, socket.SO_LINGER, struct.pack("ii", 1, 0))


def test_a_client_that_hangs_up_leaves_nothing_in_the_terminal(stack_file):
    process, line = start(str(stack_file), "--port", "0", "--no-open")
    try:
        url = line.split()[2]
        port = int(url.rstrip("/").rsplit(":", 1)[1])
        head = f"Host: 127.0.0.1:{port}\r\nContent-Type: application/json\r\n"
        requests = [
            b"GET /api/sta",  # gone in the middle of the request line
            f"GET /api/model.glb HTTP/1.1\r\n{head}\r\n".encode(),  # before the answer
            f"GET /api/state HTTP/1.1\r\n{head}\r\n".encode(),
            f'POST /api/attrs HTTP/1.1\r\n{head}Content-Length: 100\r\n\r\n{{"off'.encode(),
            f"POST /api/attrs HTTP/1.1\r\n{head}Content-Length: 15\r\n\r\n".encode()
            + b'{"offset": 0.3}',
            f"POST /api/attrs HTTP/1.1\r\n{head}Content-Length: 999999\r\n\r\n".encode(),
            f"GET /static/vendor/three/three.core.js HTTP/1.1\r\n{head}\r\n".encode(),  # large
        ]
        for _ in range(10):
            for data in requests:
                hang_up(port, data, reset=True)
                hang_up(port, data, reset=False)
        with urllib.request.urlopen(url + "api/state", timeout=60) as response:
            assert response.status == 200  # still serving
    finally:
        process.send_signal(signal.SIGINT)
        _, err = process.communicate(timeout=60)
    assert process.returncode == 0
    assert err == "shapegen edit: stopped\n", err[-2000:]
