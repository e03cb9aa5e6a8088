"""The raw-MAVLink side of PX4's AutopilotTester (PX4-Autopilot test/mavsdk_tests/autopilot_tester.cpp):
MissionRaw missions, the DO_JUMP mission, MISSION_SET_CURRENT, HOME_POSITION requests and
commands sent as COMMAND_INT.

PX4's tester uses MAVSDK's MavlinkPassthrough plugin, which MAVSDK-Python does not have; its
MavlinkDirect plugin stands in: messages go out as JSON fields (a NaN float is written as null,
which MAVSDK turns into NaN) and come back as JSON. A command's answer is the COMMAND_ACK the
vehicle sends back for it, as MavlinkPassthrough::send_command_int waits for it.
"""
from __future__ import annotations

import asyncio
import json
import math
import time
import warnings

from .autopilot_tester import AutopilotTester, log, outcome
from .checks import require

with warnings.catch_warnings():
    warnings.simplefilter("ignore", FutureWarning)
    from mavsdk.mavlink_direct import MavlinkMessage
    from mavsdk.mission_raw import MissionItem as RawItem

MAV_FRAME_GLOBAL, MAV_FRAME_MISSION, MAV_FRAME_GLOBAL_RELATIVE_ALT, MAV_FRAME_GLOBAL_INT = 0, 2, 3, 5
MAV_CMD_NAV_WAYPOINT, MAV_CMD_NAV_LAND, MAV_CMD_NAV_TAKEOFF, MAV_CMD_DO_JUMP = 16, 21, 22, 177
MAV_CMD_DO_SET_HOME, MAV_CMD_DO_REPOSITION, MAV_CMD_REQUEST_MESSAGE = 179, 192, 512
MAV_CMD_SET_MESSAGE_INTERVAL = 511
MAVLINK_MSG_ID_HOME_POSITION = 242
#: MAV_RESULT names by value.
MAV_RESULT = {0: "ACCEPTED", 1: "TEMPORARILY_REJECTED", 2: "DENIED", 3: "UNSUPPORTED", 4: "FAILED",
              5: "IN_PROGRESS", 6: "CANCELLED"}
TARGET_SYSID, TARGET_COMPID = 1, 1
#: How long a command waits for its COMMAND_ACK [s] (MAVSDK's three tries of 0.5 s, with margin).
ACK_TIMEOUT_S = 3.0


def _json(fields: dict) -> str:
    return json.dumps({k: (None if isinstance(v, float) and math.isnan(v) else v) for k, v in fields.items()})


def raw_item(seq, command, frame, param1, param2, x, y, z, current, param3=0.0, param4=0.0) -> RawItem:
    """A MissionRaw item of the main mission, autocontinue set."""
    return RawItem(seq, frame, command, current, 1, param1, param2, param3, param4, x, y, z, 0)


class AutopilotTesterRaw(AutopilotTester):
    """AutopilotTester with raw missions and raw MAVLink."""

    async def send_message(self, name: str, fields: dict) -> str:
        message = MavlinkMessage(name, 245, 190, TARGET_SYSID, TARGET_COMPID, _json(fields))
        return await outcome(self.drone.mavlink_direct.send_message(message))

    async def messages(self, name: str):
        """The fields (a dict, with `sysid`) of every `name` message that arrives."""
        async for m in self.drone.mavlink_direct.message(name):
            fields = json.loads(m.fields_json)
            fields["sysid"] = m.system_id
            yield fields

    async def command(self, name: str, fields: dict) -> str:
        """Sends COMMAND_INT or COMMAND_LONG and returns its COMMAND_ACK result ("ACCEPTED", ...,
        "NO_ACK" when none came)."""
        queue: asyncio.Queue = asyncio.Queue()

        async def acks():
            async for ack in self.messages("COMMAND_ACK"):
                if ack.get("command") == fields["command"]:
                    await queue.put(ack)
        listener = asyncio.ensure_future(acks())
        await asyncio.sleep(0.05)  # let the subscription reach mavsdk_server
        try:
            sent = await self.send_message(name, {"target_system": TARGET_SYSID, "target_component": TARGET_COMPID,
                                                  **fields})
            if sent != "SUCCESS":
                return f"SEND_{sent}"
            deadline = time.monotonic() + ACK_TIMEOUT_S
            while True:
                try:
                    ack = await asyncio.wait_for(queue.get(), max(0.01, deadline - time.monotonic()))
                except asyncio.TimeoutError:
                    return "NO_ACK"
                if ack.get("result") != 5:  # IN_PROGRESS: keep waiting
                    return MAV_RESULT.get(ack.get("result"), str(ack.get("result")))
        finally:
            listener.cancel()

    async def command_int(self, command: int, frame: int, params=(0.0, 0.0, 0.0, 0.0), x=0, y=0, z=0.0) -> str:
        return await self.command("COMMAND_INT", {
            "frame": frame, "command": command, "current": 0, "autocontinue": 0,
            "param1": params[0], "param2": params[1], "param3": params[2], "param4": params[3],
            "x": x, "y": y, "z": z})

    async def command_long(self, command: int, params=(0.0,) * 7) -> str:
        fields = {"command": command, "confirmation": 0}
        fields.update({f"param{i + 1}": float(p) for i, p in enumerate(params)})
        return await self.command("COMMAND_LONG", fields)

    async def request_message_interval(self, message_id: int, rate_hz: float) -> None:
        result = await self.command_int(MAV_CMD_SET_MESSAGE_INTERVAL, MAV_FRAME_GLOBAL,
                                        (float(message_id), 1e6 / rate_hz, 0.0, 0.0))
        require(result == "ACCEPTED", f"SET_MESSAGE_INTERVAL({message_id}, {rate_hz} Hz) accepted", result)

    async def get_home_position(self, timeout_s: float = 5) -> dict:
        """A fresh HOME_POSITION asked for with REQUEST_MESSAGE (PX4's get_home_position; its
        default time-out, not in the stored header, is taken as 5 s)."""
        got: dict = {}

        async def listen():
            async for home in self.messages("HOME_POSITION"):
                got.update(home)
        listener = asyncio.ensure_future(listen())
        await asyncio.sleep(0.05)
        await self.command_long(MAV_CMD_REQUEST_MESSAGE, (float(MAVLINK_MSG_ID_HOME_POSITION),) + (0.0,) * 6)
        ok = await self.poll(lambda: bool(got), timeout_s)
        listener.cancel()
        require(ok, f"HOME_POSITION received within {timeout_s} s of REQUEST_MESSAGE", None)
        return dict(got)

    # --- raw missions ------------------------------------------------------------------------
    def mission_raw_progress(self):
        progress = self.latest("mission_raw_progress")
        return (progress.current, progress.total) if progress is not None else (-1, -1)

    def watch_mission_raw_progress(self) -> None:
        self._watch("mission_raw_progress", self.drone.mission_raw.mission_progress())

    async def upload_raw(self, items) -> None:
        result = await outcome(self.drone.mission_raw.upload_mission(items))
        require(result == "SUCCESS", "mission_raw upload_mission() == Success", result)
        await self.sleep_for(1)  # PX4 gives the vehicle a second to take the new mission in

    async def prepare_multicopter_mission_with_do_jump(self, options, jump_repeats: int) -> int:
        """Take-off above home, north `leg`, north-east corner, DO_JUMP back to item 1 (repeated
        `jump_repeats` times), east `leg`, land at home; the DO_JUMP is item 3."""
        ct = self.get_coordinate_transformation()
        alt, leg = float(options.relative_altitude_m), options.leg_length_m

        def at(seq, command, north, east, z, current=0):
            lat, lon = ct.global_from_local(north, east)
            return raw_item(seq, command, MAV_FRAME_GLOBAL_RELATIVE_ALT, 0.0, 0.0, round(lat * 1e7), round(lon * 1e7),
                            z, current)
        jump_index = 3
        items = [at(0, MAV_CMD_NAV_TAKEOFF, 0.0, 0.0, alt, 1), at(1, MAV_CMD_NAV_WAYPOINT, leg, 0.0, alt),
                 at(2, MAV_CMD_NAV_WAYPOINT, leg, leg, alt),
                 raw_item(jump_index, MAV_CMD_DO_JUMP, MAV_FRAME_MISSION, 1.0, float(jump_repeats), 0, 0, 0.0, 0),
                 at(4, MAV_CMD_NAV_WAYPOINT, 0.0, leg, alt), at(5, MAV_CMD_NAV_LAND, 0.0, 0.0, 0.0)]
        await self.upload_raw(items)
        return jump_index

    async def start_and_wait_for_mission_sequence_raw(self, sequence: int) -> None:
        """Starts the raw mission and waits (60 s of wall time, as PX4's future) for item `sequence`."""
        reached = asyncio.Event()
        seen = {"progress": None}

        async def progress():
            async for p in self.drone.mission_raw.mission_progress():
                seen["progress"] = (p.current, p.total)
                log(f"Progress: {p.current}/{p.total}")
                if p.current >= sequence:
                    reached.set()
                    return
        listener = asyncio.ensure_future(progress())
        self.step = f"raw mission under way to item {sequence}"
        result = await outcome(self.drone.mission_raw.start_mission())
        require(result == "SUCCESS", "mission_raw start_mission() == Success", result)
        try:
            await asyncio.wait_for(reached.wait(), 60)
        except asyncio.TimeoutError:
            require(False, f"mission progress reached item {sequence} within 60 s (wall)", seen["progress"])
        finally:
            listener.cancel()

    async def send_set_current_mission_item(self, index: int) -> None:
        """One MISSION_SET_CURRENT, not repeated (MAVSDK's set_current_mission_item would resend
        until MISSION_CURRENT shows `index`, which a DO_JUMP never does)."""
        result = await self.send_message("MISSION_SET_CURRENT", {"target_system": TARGET_SYSID,
                                                                 "target_component": TARGET_COMPID, "seq": index})
        require(result == "SUCCESS", f"MISSION_SET_CURRENT({index}) sent", result)

    async def execute_rtl_when_reaching_mission_sequence(self, sequence: int) -> None:
        await self.start_and_wait_for_mission_sequence_raw(sequence)
        await self.execute_rtl()
