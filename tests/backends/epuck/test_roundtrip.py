"""Property-based round trips for every packet type (hypothesis)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from puckboard.backends.epuck import sercom_codec as sc
from puckboard.backends.epuck.blocks import ActuatorBlock, SensorBlock
from puckboard.backends.epuck.units import (
    StepCounterUnwrapper,
    rgb565_decode,
    rgb565_encode,
    wrap_int16,
)
from puckboard.backends.epuck.wifi_codec import (
    EMPTY_PACKET,
    IMAGE,
    SENSORS,
    CommandFramer,
    PacketFramer,
    WifiCommand,
    decode_image,
    encode_image_packet,
    encode_sensor_packet,
)

int16 = st.integers(-0x8000, 0x7FFF)
uint16 = st.integers(0, 0xFFFF)
byte = st.integers(0, 255)
f32 = st.floats(width=32, allow_nan=False, allow_infinity=False)

actuators = st.builds(
    ActuatorBlock,
    left=int16,
    right=int16,
    leds=byte,
    rgb=st.tuples(*([st.integers(0, 100)] * 12)),
    sound=byte,
    settings=byte,
)

sensor_blocks = st.builds(
    SensorBlock,
    acc=st.tuples(int16, int16, int16),
    acceleration=f32,
    orientation=f32,
    inclination=f32,
    gyro=st.tuples(int16, int16, int16),
    magnetometer=st.tuples(f32, f32, f32),
    temperature=st.integers(-40, 100),
    proximity=st.tuples(*([st.integers(-4096, 4096)] * 8)),
    ambient=st.tuples(*([st.integers(0, 4096)] * 8)),
    tof_mm=uint16,
    microphones=st.tuples(uint16, uint16, uint16, uint16),
    steps=st.tuples(int16, int16),
    battery=uint16,
    sd_state=byte,
    tv_remote=st.tuples(byte, byte, byte),
    selector=st.integers(0, 15),
    ground=st.tuples(*([st.integers(0, 4096)] * 3)),
    ground_ambient=st.tuples(uint16, uint16, uint16),
    button=st.integers(0, 1),
)

# images whose channels are exactly representable in RGB565 (low bits zero)
rgb565_images = st.integers(1, 12).flatmap(
    lambda h: st.integers(1, 12).flatmap(
        lambda w: arrays(np.uint8, (h, w, 3), elements=st.integers(0, 255))
    )
)


def _representable(img: np.ndarray) -> np.ndarray:
    out = img.copy()
    out[..., 0] &= 0xF8
    out[..., 1] &= 0xFC
    out[..., 2] &= 0xF8
    return out


@given(actuators)
def test_actuator_block_round_trip(block: ActuatorBlock) -> None:
    data = block.encode()
    assert len(data) == 19
    assert ActuatorBlock.decode(data) == block


@given(actuators, st.booleans(), st.booleans())
def test_wifi_command_round_trip(block: ActuatorBlock, image: bool, sensors: bool) -> None:
    cmd = WifiCommand(block, image=image, sensors=sensors)
    data = cmd.encode()
    assert len(data) == 21 and data[0] == 0x80
    assert WifiCommand.decode(data) == cmd


@given(sensor_blocks, st.booleans())
def test_sensor_block_round_trip(block: SensorBlock, wifi: bool) -> None:
    data = block.encode(wifi=wifi)
    assert len(data) == (104 if wifi else 103)
    back = SensorBlock.decode(data)
    expected = block if wifi else SensorBlock(**{**block.__dict__, "button": 0})
    assert back == expected


@given(rgb565_images)
def test_rgb565_round_trip(img: np.ndarray) -> None:
    img = _representable(img)
    h, w = img.shape[:2]
    assert np.array_equal(rgb565_decode(rgb565_encode(img), w, h), img)


@settings(max_examples=10, deadline=None)
@given(st.integers(0, 255), st.integers(0, 255), st.integers(0, 255))
def test_wifi_image_packet_round_trip(r: int, g: int, b: int) -> None:
    img = np.zeros((120, 160, 3), dtype=np.uint8)
    img[:60] = (r, g, b)  # top half one colour: orientation must survive
    img = _representable(img)
    packet = encode_image_packet(img)
    assert packet[0] == IMAGE and len(packet) == 1 + 38400
    assert np.array_equal(decode_image(packet[1:]), img)


@given(rgb565_images, st.sampled_from([sc.CAMERA_RGB565, sc.CAMERA_GREY]))
def test_sercom_camera_round_trip(img: np.ndarray, mode: int) -> None:
    img = _representable(img)
    if mode == sc.CAMERA_GREY:
        img = np.repeat(img[..., :1], 3, axis=2)
    data = sc.encode_camera(img, mode)
    header, body = data[:3], data[3:]
    assert sc.camera_body_size(header) == len(body)
    assert np.array_equal(sc.decode_camera(header, body), img)


commands = st.one_of(
    st.tuples(st.sampled_from([sc.SET_SPEED, sc.SET_STEPS]), st.binary(min_size=4, max_size=4)),
    st.tuples(st.just(sc.SET_LED), st.binary(min_size=2, max_size=2)),
    st.tuples(st.just(sc.ALL_ACTUATORS), actuators.map(lambda a: a.encode())),
    st.tuples(
        st.sampled_from(
            [
                sc.GET_PROXIMITY,
                sc.GET_GROUND,
                sc.GET_STEPS,
                sc.GET_ACCELEROMETER,
                sc.ALL_SENSORS,
                sc.GET_IMAGE,
            ]
        ),
        st.just(b""),
    ),
)


@given(
    st.lists(st.lists(commands, min_size=1, max_size=5), min_size=1, max_size=4), st.integers(1, 9)
)
def test_sercom_request_round_trip(requests: list[list[tuple[int, bytes]]], chunk: int) -> None:
    stream = b"".join(sc.encode_request(r) for r in requests)
    parser = sc.RequestParser()
    got = []
    for i in range(0, len(stream), chunk):
        got += parser.feed(stream[i : i + chunk])
    assert got == [("binary", r) for r in requests]


@given(st.lists(st.tuples(int16, st.integers(-0x7FFF, 0x7FFF))))
def test_int16_lists_round_trip(pairs: list[tuple[int, int]]) -> None:
    flat = [v for p in pairs for v in p]
    assert sc.decode_int16s(sc.encode_int16s(flat)) == tuple(flat)


@given(
    st.lists(st.one_of(st.just("empty"), st.just("sensors"), sensor_blocks), max_size=6),
    st.integers(1, 50),
)
def test_packet_framer_round_trip(items: list, chunk: int) -> None:
    stream = b""
    expected = []
    for item in items:
        if item == "empty":
            stream += EMPTY_PACKET
            expected.append((0x03, b""))
        else:
            block = item if isinstance(item, SensorBlock) else SensorBlock()
            stream += encode_sensor_packet(block)
            expected.append((SENSORS, block.encode(wifi=True)))
    framer = PacketFramer()
    got = []
    for i in range(0, len(stream), chunk):
        framer.feed(stream[i : i + chunk])
        got += framer.packets()
    assert got == expected
    assert framer.skipped == 0


@given(
    st.lists(st.tuples(actuators, st.booleans(), st.booleans()), max_size=5), st.binary(max_size=10)
)
def test_command_framer_skips_leading_garbage(cmds: list, garbage: bytes) -> None:
    garbage = bytes(b for b in garbage if b != 0x80)
    stream = garbage + b"".join(WifiCommand(a, image=i, sensors=s).encode() for a, i, s in cmds)
    framer = CommandFramer()
    framer.feed(stream)
    assert framer.commands() == [WifiCommand(a, image=i, sensors=s) for a, i, s in cmds]
    assert framer.skipped == len(garbage)


@given(st.lists(st.integers(-30000, 30000), max_size=60))
def test_step_counter_unwraps_any_walk(moves: list[int]) -> None:
    u = StepCounterUnwrapper()
    true = [5, -7]
    u.update(wrap_int16(true[0]), wrap_int16(true[1]))
    for m in moves:
        true[0] += m
        true[1] -= m
        got = u.update(wrap_int16(true[0]), wrap_int16(true[1]))
        assert got == (true[0] - 5, true[1] + 7)


@given(sensor_blocks, st.integers(-128, 127))
def test_sensor_block_check_rejects_impossible_temperatures(
    block: SensorBlock, temperature: int
) -> None:
    data = bytearray(block.encode(wifi=True))
    data[36] = temperature & 0xFF
    if -40 <= temperature <= 100:
        assert SensorBlock.decode(bytes(data)).temperature == temperature
    else:
        with pytest.raises(ValueError, match="temperature"):
            SensorBlock.decode(bytes(data))
