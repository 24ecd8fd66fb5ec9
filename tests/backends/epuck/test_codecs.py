"""Codec tests against byte fixtures written by hand from the protocol documentation.

The fixtures are spelled out byte by byte (little-endian int16: low byte first) from the
offsets in GCtronic's Wi-Fi protocol description and the firmware's Asercom2.c, not
produced by our encoders, so an encoder and decoder that agree on a wrong layout fail.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from puckboard.backends.epuck import sercom_codec as sc
from puckboard.backends.epuck.blocks import (
    ActuatorBlock,
    ImplausibleDataError,
    SensorBlock,
)
from puckboard.backends.epuck.units import (
    StepCounterUnwrapper,
    acceleration_from_raw,
    calibrated_from_distance,
    distance_from_calibrated,
    ground_value_from_raw,
    rad_s_to_steps_s,
    rgb565_decode,
    steps_s_to_rad_s,
)
from puckboard.backends.epuck.wifi_codec import (
    IMAGE_SIZE,
    PacketFramer,
    WifiCommand,
    decode_image,
)
from puckboard.profile import EPUCK2, apply_overrides

# -- Wi-Fi command 0x80 --------------------------------------------------------------------
# id 0x80; request 0x02 (sensor stream); settings 0; left +500 = 0x01F4; right -500 = 0xFE0C;
# LEDs: body (bit4) = 0x10; LED2 red 100 = 0x64, the other 11 RGB bytes 0; sound stop 0x20.
WIFI_COMMAND = bytes([0x80, 0x02, 0x00, 0xF4, 0x01, 0x0C, 0xFE, 0x10, 0x64] + [0x00] * 11 + [0x20])


def test_wifi_command_fixture_decodes() -> None:
    assert len(WIFI_COMMAND) == 21
    cmd = WifiCommand.decode(WIFI_COMMAND)
    assert cmd.sensors and not cmd.image
    assert (cmd.actuators.left, cmd.actuators.right) == (500, -500)
    assert cmd.actuators.leds == 0x10
    assert cmd.actuators.rgb[0] == 100 and sum(cmd.actuators.rgb) == 100
    assert cmd.actuators.sound == 0x20


def test_wifi_command_fixture_encodes() -> None:
    block = ActuatorBlock(left=500, right=-500, leds=0x10, rgb=(100,) + (0,) * 11, sound=0x20)
    assert WifiCommand(block, sensors=True).encode() == WIFI_COMMAND


def test_wifi_command_request_bits() -> None:
    assert WifiCommand(image=True).encode()[1] == 0x01
    assert WifiCommand(image=True, sensors=True).encode()[1] == 0x03
    assert WifiCommand().encode()[1] == 0x00


def test_wifi_command_rejects_wrong_id() -> None:
    with pytest.raises(ValueError, match="0x80"):
        WifiCommand.decode(b"\x81" + WIFI_COMMAND[1:])


# -- sensor block (Wi-Fi 0x02 payload: 104 bytes; sercom 0x08 reply: 103 bytes) ----------
def _sensor_fixture(size: int) -> bytes:
    b = bytearray(size)
    b[0:2] = bytes([0xFB, 0xFF])  # acc x = -5
    b[4:6] = bytes([0x00, 0x03])  # acc z = 768 (1 g)
    b[36] = 0x1A  # temperature 26 °C
    b[37:39] = bytes([0x2C, 0x01])  # ps0 = 300
    b[51:53] = bytes([0xFD, 0xFF])  # ps7 = -3 (calibrated values go slightly negative)
    b[53:55] = bytes([0xA0, 0x0F])  # ambient ps0 = 4000
    b[69:71] = bytes([0x2D, 0x00])  # ToF 45 mm
    b[79:81] = bytes([0xFF, 0xFF])  # steps left = -1
    b[81:83] = bytes([0xD2, 0x04])  # steps right = 1234
    b[83:85] = bytes([0x10, 0x0E])  # battery 3600
    b[89] = 15  # selector
    b[90:92] = bytes([0xE8, 0x03])  # ground left 1000
    b[92:94] = bytes([0x64, 0x00])  # ground centre 100
    b[94:96] = bytes([0xFF, 0x03])  # ground right 1023
    if size == 104:
        b[102] = 1  # button pressed
    return bytes(b)


@pytest.mark.parametrize("size", [104, 103])
def test_sensor_block_fixture_decodes(size: int) -> None:
    block = SensorBlock.decode(_sensor_fixture(size))
    assert block.acc == (-5, 0, 768)
    assert block.temperature == 26
    assert block.proximity[0] == 300 and block.proximity[7] == -3
    assert block.ambient[0] == 4000
    assert block.tof_mm == 45
    assert block.steps == (-1, 1234)
    assert block.battery == 3600
    assert block.selector == 15
    assert block.ground == (1000, 100, 1023)
    assert block.button == (1 if size == 104 else 0)


@pytest.mark.parametrize("size", [104, 103])
def test_sensor_block_encodes_fixture(size: int) -> None:
    block = SensorBlock(
        acc=(-5, 0, 768),
        acceleration=0.0,
        temperature=26,
        proximity=(300, 0, 0, 0, 0, 0, 0, -3),
        ambient=(4000,) + (0,) * 7,
        tof_mm=45,
        steps=(-1, 1234),
        battery=3600,
        selector=15,
        ground=(1000, 100, 1023),
        ground_ambient=(0, 0, 0),
        button=1,
    )
    assert block.encode(wifi=size == 104) == _sensor_fixture(size)


def test_sensor_block_rejects_implausible_bytes() -> None:
    bad = bytearray(_sensor_fixture(104))
    bad[89] = 200  # a selector has 16 positions
    with pytest.raises(ImplausibleDataError, match="selector"):
        SensorBlock.decode(bytes(bad))
    with pytest.raises(ValueError, match="103"):
        SensorBlock.decode(bytes(50))


# -- Wi-Fi framing and resynchronisation ---------------------------------------------------
def test_framer_splits_packets_and_resyncs_after_garbage() -> None:
    framer = PacketFramer()
    stream = b"\x03" + b"\x55\xaa\x99" + b"\x02" + _sensor_fixture(104) + b"\x03"
    for i in range(0, len(stream), 7):  # arrives in arbitrary chunks
        framer.feed(stream[i : i + 7])
    packets = framer.packets()
    assert [p[0] for p in packets] == [0x03, 0x02, 0x03]
    assert SensorBlock.decode(packets[1][1]).steps == (-1, 1234)
    assert framer.skipped == 3


def test_image_packet_size_and_orientation() -> None:
    payload = bytearray(IMAGE_SIZE)
    payload[0:2] = bytes([0xF8, 0x00])  # top-left pixel pure red
    payload[-2:] = bytes([0x00, 0x1F])  # bottom-right pixel pure blue
    img = decode_image(bytes(payload))
    assert img.shape == (120, 160, 3)
    assert tuple(img[0, 0]) == (248, 0, 0)
    assert tuple(img[119, 159]) == (0, 0, 248)
    assert img[60, 80].sum() == 0


# -- RGB565 --------------------------------------------------------------------------------
@pytest.mark.parametrize(
    ("two_bytes", "rgb"),
    [
        (b"\xff\xff", (248, 252, 248)),  # white, low bits unfilled as on the robot
        (b"\xf8\x00", (248, 0, 0)),  # red
        (b"\x07\xe0", (0, 252, 0)),  # green
        (b"\x00\x1f", (0, 0, 248)),  # blue
        (b"\x00\x00", (0, 0, 0)),
        (b"\x84\x10", (128, 128, 128)),  # 10000 100000 10000
    ],
)
def test_rgb565_known_pixels(two_bytes: bytes, rgb: tuple[int, int, int]) -> None:
    assert tuple(rgb565_decode(two_bytes, 1, 1)[0, 0]) == rgb


def test_rgb565_rows_are_row_major() -> None:
    # 2×2 image: row 0 = red, green; row 1 = blue, white
    data = b"\xf8\x00" + b"\x07\xe0" + b"\x00\x1f" + b"\xff\xff"
    img = rgb565_decode(data, 2, 2)
    assert tuple(img[0, 1]) == (0, 252, 0)
    assert tuple(img[1, 0]) == (0, 0, 248)


# -- advanced sercom -----------------------------------------------------------------------
def test_sercom_wire_bytes() -> None:
    assert sc.binary("N") == 0xB2
    assert sc.binary("D") == 0xBC
    assert sc.binary("Q") == 0xAF
    assert sc.binary("I") == 0xB7
    assert sc.binary("a") == 0x9F
    assert sc.binary(0x08) == 0xF8
    assert sc.binary(0x09) == 0xF7


def test_sercom_request_fixtures() -> None:
    # [-'N'][-'Q'][0]
    assert sc.encode_request([(sc.GET_PROXIMITY, b""), (sc.GET_STEPS, b"")]) == bytes.fromhex(
        "b2af00"
    )
    # [-'D'] +100 (64 00) -100 (9c ff) [0]
    speeds = sc.encode_int16s((100, -100))
    assert sc.encode_request([(sc.SET_SPEED, speeds)]) == bytes.fromhex("bc64009cff00")
    # e-puck2 cycle: [-0x09][19 bytes][-0x08][0] = 22 bytes, as GCtronic's driver sends
    block = ActuatorBlock(left=200, right=300).encode()
    request = sc.encode_request([(sc.ALL_ACTUATORS, block), (sc.ALL_SENSORS, b"")])
    assert len(request) == 22
    assert request[0] == 0xF7 and request[-2:] == b"\xf8\x00"
    assert request[1:6] == bytes([0x00, 0xC8, 0x00, 0x2C, 0x01])  # settings, 200, 300


def test_sercom_request_rejects_wrong_parameters() -> None:
    with pytest.raises(ValueError, match="parameter bytes"):
        sc.encode_request([(sc.SET_SPEED, b"\x00")])


def test_sercom_reply_fixtures() -> None:
    # -'N' reply: 8 × int16, ps0 = 1 (01 00) ... ps7 = -2 (fe ff)
    reply = bytes.fromhex("0100" + "0000" * 6 + "feff")
    assert sc.decode_int16s(reply, 8) == (1, 0, 0, 0, 0, 0, 0, -2)
    assert sc.reply_size(sc.GET_PROXIMITY) == 16
    assert sc.reply_size(sc.GET_GROUND) == 6
    assert sc.reply_size(sc.ALL_SENSORS) == 103
    assert sc.reply_size(sc.GET_IMAGE) is None
    assert sc.reply_size(sc.SET_SPEED) == 0


def test_sercom_camera_fixture() -> None:
    header = bytes([1, 2, 1])  # RGB565, 2 wide, 1 high
    img = sc.decode_camera(header, b"\xf8\x00\x00\x1f")
    assert img.shape == (1, 2, 3)
    assert tuple(img[0, 0]) == (248, 0, 0) and tuple(img[0, 1]) == (0, 0, 248)
    grey = sc.decode_camera(bytes([0, 2, 1]), b"\x10\x80")
    assert tuple(grey[0, 1]) == (128, 128, 128)
    with pytest.raises(ValueError, match="implausible camera header"):
        sc.camera_body_size(bytes([7, 2, 1]))


def test_request_parser_splits_binary_and_ascii() -> None:
    parser = sc.RequestParser()
    out = parser.feed(bytes.fromhex("bc6400"))  # incomplete: parameters cut short
    assert out == []
    out = parser.feed(bytes.fromhex("9cff") + b"\xb2\x00" + b"V\r")
    assert out == [("binary", [(0xBC, bytes.fromhex("64009cff")), (0xB2, b"")]), ("ascii", "V")]


# -- unit conversions ----------------------------------------------------------------------
def test_steps_and_rad_per_second() -> None:
    assert steps_s_to_rad_s(1000, EPUCK2) == pytest.approx(2 * math.pi)
    assert rad_s_to_steps_s(math.pi, EPUCK2) == 500
    assert rad_s_to_steps_s(-2 * math.pi, EPUCK2) == -1000


def test_step_counter_wraps_forward_and_back() -> None:
    u = StepCounterUnwrapper()
    assert u.update(32760, -32760) == (0, 0)
    assert u.update(-32766, 32766) == (10, -10)  # crossed +32767 / -32768
    assert u.update(32760, -32760) == (0, 0)  # and back again
    # many laps of the counter, forward on the left and backward on the right, in
    # increments of 20000 steps written as the int16 the robot would report
    u.reset()
    raw = [0, 20000, -25536, -5536, 14464, -31072, -11072, 8928, 28928, -16608, 3392]
    for k, r in enumerate(raw):
        assert u.update(r, -r) == (20000 * k, -20000 * k)


def test_proximity_curve_points_and_clipping() -> None:
    d = distance_from_calibrated([0.0, -20.0, 4028.0, 5000.0, 316.65, 167.74, 52.81], EPUCK2)
    assert d[0] == 0.05 and d[1] == 0.05  # nothing seen: exactly the range
    assert d[6] == 0.05  # the curve's value at 5 cm is still nothing
    assert d[2] == pytest.approx(0.0, abs=1e-6) and d[3] == 0.0
    assert d[4] == pytest.approx(0.02, abs=1e-4)
    assert d[5] == pytest.approx(0.03, abs=1e-4)
    # the emulator's direction is the inverse inside the range
    distances = np.linspace(0.0, 0.049, 50)
    assert np.allclose(
        distance_from_calibrated(calibrated_from_distance(distances), EPUCK2), distances, atol=1e-9
    )
    assert calibrated_from_distance([0.07, np.inf]).tolist() == [0.0, 0.0]
    # a robot whose sensors stop at 4 cm reads values of 4.5 cm as nothing
    short = apply_overrides(EPUCK2, {"prox_max_distance": 0.04}, source="test")
    at = calibrated_from_distance([0.035, 0.045])
    assert distance_from_calibrated(at, short).tolist() == pytest.approx([0.035, 0.05])


def test_ground_and_acceleration() -> None:
    assert ground_value_from_raw([0, 1023, 2000, -5]).tolist() == [0.0, 1.0, 1.0, 0.0]
    ax, ay, az = acceleration_from_raw((0, -768, 768))
    assert (ax, ay, az) == pytest.approx((0.0, -9.81, 9.81))
    # e-puck1 convention: 2048 at 0 g, 800 counts per g
    assert acceleration_from_raw((2048, 2848, 1248), 800.0, 2048.0) == pytest.approx(
        (0, 9.81, -9.81)
    )
