"""PX4's test_param_ftp.cpp (PX4-Autopilot test/mavsdk_tests): the parameters over MAVLink FTP in
ArduPilot's packed format, `@PARAM/param.pck?withdefaults=1` downloaded and compared value for value
(bit for bit, type by type) with the PARAM_VALUE list; and a one-float packed file uploaded to
`@PARAM`, after which that parameter reads back as the uploaded value (then it is restored).

The packed format: a header of magic 0x671B or 0x671C, the count and the total (u16 each), then
per parameter a type byte (low nibble: 3 int32, 4 float; bit 4: a default follows), a byte of
(name length - 1) << 4 | characters shared with the previous name, the name's new characters,
the value and, if flagged, the default; zero bytes are padding.
"""
import asyncio
import pathlib
import struct
import tempfile
import warnings

from . import CONNECTION_URL, case
from .autopilot_tester import AutopilotTester, outcome, value_of
from .checks import approx, check, require

with warnings.catch_warnings():
    warnings.simplefilter("ignore", FutureWarning)
    from mavsdk.ftp import FtpError

MAGICS = (0x671B, 0x671C)
TYPE_INT32, TYPE_FLOAT = 3, 4


def decode_param_pck(data: bytes):
    """(count, total, {name: (type, value bits)}) of a packed file; None when it does not parse."""
    if len(data) < 6:
        return None
    magic, count, total = struct.unpack_from("<HHH", data)
    if magic not in MAGICS:
        return None
    params, previous, i = {}, "", 6
    while i < len(data):
        if data[i] == 0:
            i += 1
            continue
        if i + 2 > len(data):
            return None
        kind, has_default = data[i] & 0x0F, (data[i] >> 4) & 1
        common, length = data[i + 1] & 0x0F, (data[i + 1] >> 4) + 1
        i += 2
        if common > len(previous) or common + length > 16 or i + length + 4 > len(data):
            return None
        name = previous[:common] + data[i:i + length].decode("ascii", "replace")
        i += length
        bits = struct.unpack_from("<I", data, i)[0]
        i += 4 + (4 if has_default else 0)
        if has_default and i > len(data):
            return None
        params[name] = (kind, bits)
        previous = name
    return (count, total, params) if len(params) == count else None


def encode_one_float(name: str, value: float) -> bytes:
    body = bytes([TYPE_FLOAT, (len(name) - 1) << 4]) + name.encode("ascii") + struct.pack("<f", value)
    return struct.pack("<HHH", 0x671B, 1, 6 + len(body)) + body


async def _ftp(progress, label) -> str:
    """Runs an FTP transfer (an async generator of progress) for at most 60 s of wall time."""
    async def run():
        try:
            async for _ in progress:
                pass
            return "SUCCESS"
        except FtpError as error:
            return error._result.result.name
    try:
        return await asyncio.wait_for(run(), 60)
    except asyncio.TimeoutError:
        require(False, f"{label} finished within 60 s", "still running")


@case("Parameters download via MAVLink FTP", "[multicopter]")
async def parameters_download_via_mavlink_ftp(url: str = CONNECTION_URL) -> None:
    tester = AutopilotTester()
    await tester.connect(url)
    result, every = await value_of(tester.drone.param.get_all_params())
    count = len(every.int_params) + len(every.float_params) if every is not None else 0
    require(count > 100, "get_all_params() lists more than 100 parameters", f"{result}, {count}")
    local = pathlib.Path(tempfile.mkdtemp(prefix="px4_mavsdk_tests_param_ftp"))
    remote = "@PARAM/param.pck?withdefaults=1"
    result = await _ftp(tester.drone.ftp.download(remote, str(local), True), f"download {remote}")
    require(result == "SUCCESS", f"FTP download {remote} == Success", result)
    path = local / "param.pck?withdefaults=1"
    require(path.exists(), "the downloaded file is there", sorted(p.name for p in local.iterdir()))
    decoded = decode_param_pck(path.read_bytes())
    require(decoded is not None, "the packed file decodes", path.read_bytes()[:16].hex())
    number, total, packed = decoded
    check(number == total, "packed count == total", (number, total))
    compared = 0
    for p in every.int_params:
        if p.name == "_HASH_CHECK":
            continue
        require(p.name in packed, f"{p.name} in the packed file", None)
        check(packed[p.name][0] == TYPE_INT32, "an int parameter packed as int32", (p.name, packed[p.name][0]))
        check(packed[p.name][1] == struct.unpack("<I", struct.pack("<i", p.value))[0],
              "an int parameter's packed value equals PARAM_VALUE's", (p.name, packed[p.name][1], p.value))
        compared += 1
    for p in every.float_params:
        require(p.name in packed, f"{p.name} in the packed file", None)
        check(packed[p.name][0] == TYPE_FLOAT, "a float parameter packed as float", (p.name, packed[p.name][0]))
        check(packed[p.name][1] == struct.unpack("<I", struct.pack("<f", p.value))[0],
              "a float parameter's packed bits equal PARAM_VALUE's", (p.name, packed[p.name][1], p.value))
        compared += 1
    check(compared == len(packed), "every packed parameter compared", (compared, len(packed)))


@case("Parameters upload via MAVLink FTP", "[multicopter]")
async def parameters_upload_via_mavlink_ftp(url: str = CONNECTION_URL) -> None:
    tester = AutopilotTester()
    await tester.connect(url)
    param = tester.drone.param
    result, every = await value_of(param.get_all_params())
    require(every is not None and bool(every.float_params), "get_all_params() has float parameters", result)
    name, original = every.float_params[0].name, every.float_params[0].value
    updated = original + 1.0
    local = pathlib.Path(tempfile.mkdtemp(prefix="px4_mavsdk_tests_param_ftp_up")) / "param.pck"
    local.write_bytes(encode_one_float(name, updated))
    result = await _ftp(tester.drone.ftp.upload(str(local), "@PARAM"), "upload to @PARAM")
    require(result == "SUCCESS", "FTP upload of param.pck to @PARAM == Success", result)
    result, value = await value_of(param.get_param_float(name))
    require(result == "SUCCESS", f"get_param_float({name}) == Success", result)
    check(approx(value, updated),
          f"{name} reads back the uploaded {updated}", value)
    result = await outcome(param.set_param_float(name, original))
    require(result == "SUCCESS", f"set_param_float({name}, {original}) == Success", result)
