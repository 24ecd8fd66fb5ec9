"""Malformed, random and hostile frames: every one gets an answer or is dropped, and the
server then still serves a well-formed client."""

from __future__ import annotations

import logging
import uuid

import cbor2
import pytest
import zmq
from coppeliasim_support import start_server, stop_server
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from puckboard.backends.coppeliasim.adapter import EPuckVRep
from puckboard.records import Sensor

pytestmark = pytest.mark.network

FUZZ = settings(
    max_examples=80,
    deadline=None,
    database=None,
    suppress_health_check=[HealthCheck.too_slow],
)

cbor_values = st.recursive(
    st.none()
    | st.booleans()
    | st.integers(min_value=-(2**70), max_value=2**70)
    | st.floats(allow_nan=True, allow_infinity=True)
    | st.text(max_size=20)
    | st.binary(max_size=20),
    lambda children: (
        st.lists(children, max_size=5) | st.dictionaries(st.text(max_size=8), children, max_size=5)
    ),
    max_leaves=20,
)

HOSTILE_FRAMES = [
    b"",
    b"\x81" * 100_000,  # nesting bomb
    b"\x9b\xff\xff\xff\xff\xff\xff\xff\xff",  # an array claiming 2^64 items
    b"\x5b\x00\x00\x00\xff\xff\xff\xff\xff",  # a byte string claiming a terabyte
    b"\xd8\x23\x63a+b",  # a regular expression tag
    cbor2.dumps({"func": "sim.getObject", "args": "not a list", "uuid": "u"}),
    cbor2.dumps({"func": 7, "args": [], "uuid": "u"}),
    cbor2.dumps({"func": "sim.getObject", "args": [], "uuid": 12}),
    cbor2.dumps({"func": "x" * 5000, "args": [], "uuid": "u"}),
    cbor2.dumps([1, 2, 3]),
]


def test_the_server_survives_anything_and_still_serves(caplog):
    caplog.set_level(logging.ERROR, logger="puckboard.backends.coppeliasim.server")
    srv = start_server(stepping_timeout=0.2)
    ctx = zmq.Context()
    req = ctx.socket(zmq.REQ)
    req.setsockopt(zmq.LINGER, 0)
    req.setsockopt(zmq.RCVTIMEO, 5000)
    req.connect(f"tcp://127.0.0.1:{srv.port}")
    dealer = ctx.socket(zmq.DEALER)
    dealer.setsockopt(zmq.LINGER, 0)
    dealer.connect(f"tcp://127.0.0.1:{srv.port}")
    functions = sorted(srv.api.functions) + ["zmqRemoteApi.info", "zmqRemoteApi.require"]

    def ask(frame: bytes) -> dict:
        req.send(frame)
        reply = cbor2.loads(req.recv())  # a reply must come: a timeout raises zmq.Again
        assert isinstance(reply, dict)
        return reply

    try:
        for frame in HOSTILE_FRAMES:
            assert "err" in ask(frame)
        # an absurd argsL is ignored rather than padded to a billion arguments
        huge = {"func": "sim.getObject", "args": ["/ePuck"], "argsL": 10**9, "uuid": "u"}
        assert ask(cbor2.dumps(huge))["ret"][0] > 0

        @FUZZ
        @given(st.binary(max_size=200))
        def random_bytes(frame: bytes) -> None:
            reply = ask(frame)
            assert set(reply) & {"err", "ret", "func"} or reply == {}

        @FUZZ
        @given(cbor_values)
        def random_cbor(value: object) -> None:
            reply = ask(cbor2.dumps(value))
            assert set(reply) & {"err", "ret", "func"} or reply == {}

        @FUZZ
        @given(st.sampled_from(functions), st.lists(cbor_values, max_size=6), st.booleans())
        def served_functions_with_random_arguments(func: str, args: list, fresh: bool) -> None:
            client = str(uuid.uuid4()) if fresh else "fuzz-client"
            reply = ask(cbor2.dumps({"func": func, "args": args, "uuid": client}))
            assert set(reply) & {"err", "ret", "func"}, reply
            if "err" in reply:
                assert isinstance(reply["err"], str) and reply["err"]

        @FUZZ
        @given(st.lists(st.binary(max_size=30), min_size=1, max_size=4))
        def multipart_from_a_dealer(frames: list[bytes]) -> None:
            dealer.send_multipart(frames)  # no REQ envelope: answered or dropped, never fatal

        random_bytes()
        random_cbor()
        served_functions_with_random_arguments()
        multipart_from_a_dealer()
        assert srv._thread is not None and srv._thread.is_alive()
        # every bad input was refused by a check, none reached an internal error
        assert not [r.getMessage() for r in caplog.records if r.levelno >= logging.ERROR]

        # a well-formed client is still served, stepping included
        robot = EPuckVRep("after", object_path="/ePuck[1]", port=srv.port, timeout=5.0)
        try:
            robot.start_simulation()
            robot.set_wheel_speeds(2.0, 2.0)
            before = robot.link.call("sim.getSimulationTime")
            robot.step(2)
            after = robot.link.call("sim.getSimulationTime")
            assert after == pytest.approx(before + 2 * robot.stepper.dt)
            assert robot.sense_all()[Sensor.WHEEL_SPEEDS].left == pytest.approx(2.0, rel=0.3)
        finally:
            robot.close()
    finally:
        req.close(0)
        dealer.close(0)
        ctx.term()
        stop_server(srv)
