"""pymavlink, loaded for MAVLink 2.

pymavlink picks its wire protocol when it is first imported (the ``MAVLINK20`` environment
variable); this module sets it first and, if pymavlink was already loaded for MAVLink 1, loads
the dialect again for MAVLink 2.
"""
import os

os.environ["MAVLINK20"] = "1"
from pymavlink import mavutil  # noqa: E402

if mavutil.mavlink.WIRE_PROTOCOL_VERSION != "2.0":
    mavutil.set_dialect(mavutil.current_dialect)

#: The generated MAVLink 2 dialect module (message classes, enums and ``MAV_*`` constants).
mavlink = mavutil.mavlink

__all__ = ["mavlink", "mavutil"]
