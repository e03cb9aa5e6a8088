"""A rotorpilot ULog flight log as the columns of a ``run.csv`` (``plot_run.py``'s input).

Every signal is taken at the times of ``vehicle_local_position`` (every tick with the full
profile of ``sim --out`` and ``fly --log``, every 20 ms with ``run --log``'s default profile);
topics logged at other rates are held at their latest record (NaN before their first). Columns
whose topics are absent from the log (the estimator's while it was off, the control's while the
motors never ran) are left out, as ``run.csv`` leaves them empty.

Rotor columns ``omega_i`` hold ``actuator_motors.control[i]``, the commanded speed over the
maximum [-] (the ULog does not carry the rotors' true speeds): ``ROTOR_UNIT`` says so.
"""
import numpy as np

ROTOR_UNIT = "ω_i / ω_max (commanded) [-]"
MAX_MOTORS = 12


def _quat_to_euler(w, x, y, z):
    """ZYX Euler angles (roll, pitch, yaw) [rad] of unit quaternions (w, x, y, z), body → world."""
    roll = np.arctan2(2 * (w * x + y * z), 1 - 2 * (x * x + y * y))
    pitch = np.arcsin(np.clip(2 * (w * y - z * x), -1.0, 1.0))
    yaw = np.arctan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z))
    return roll, pitch, yaw


def _held(t_us, topic):
    """Indices into ``topic``'s records of the latest record at or before each time of ``t_us``
    (-1 before the first)."""
    return np.searchsorted(topic["timestamp"], t_us, side="right") - 1


def load_ulog(path):
    """(columns, rotor column names, info) of the ULog file ``path``; info holds what the log says
    of the run (``true_mass_kg``, ``mass_mismatch_force_n``, controller, airframe). Raises
    ``ValueError`` naming what is missing."""
    from pyulog import ULog

    ulog = ULog(str(path))
    data = {d.name: d.data for d in ulog.data_list if d.multi_id == 0}
    if "vehicle_local_position" not in data:
        raise ValueError("no vehicle_local_position records: not a flight log of rotorpilot")
    lpos = data["vehicle_local_position"]
    t_us = lpos["timestamp"]
    cols = {"t": t_us * 1e-6}
    for axis in "xyz":
        cols[axis] = lpos[axis].astype(np.float64)

    def take(topic, fields, names):
        """Columns `names` from `fields` of `topic`, held at the position times; False if absent."""
        if topic not in data:
            return False
        rec = data[topic]
        idx = _held(t_us, rec)
        for field, name in zip(fields, names):
            values = rec[field].astype(np.float64)[np.maximum(idx, 0)]
            cols[name] = np.where(idx >= 0, values, np.nan)
        return True

    take("vehicle_local_position_setpoint", ("x", "y", "z"), ("x_ref", "y_ref", "z_ref"))
    take("controller_errors", [f"e_p[{i}]" for i in range(3)] + [f"e_v[{i}]" for i in range(3)]
         + [f"e_r[{i}]" for i in range(3)] + [f"e_omega[{i}]" for i in range(3)],
         ("ex", "ey", "ez", "evx", "evy", "evz", "eR_x", "eR_y", "eR_z", "ew_x", "ew_y", "ew_z"))
    att = data.get("vehicle_attitude")
    if att is not None:
        idx = np.maximum(_held(t_us, att), 0)
        q = [att[f"q[{i}]"].astype(np.float64)[idx] for i in range(4)]
        cols["roll"], cols["pitch"], cols["yaw"] = _quat_to_euler(*q)
    sp = data.get("vehicle_attitude_setpoint")
    if sp is not None:
        idx = _held(t_us, sp)
        q = [sp[f"q_d[{i}]"].astype(np.float64)[np.maximum(idx, 0)] for i in range(4)]
        for name, angle in zip(("roll_ref", "pitch_ref", "yaw_ref"), _quat_to_euler(*q)):
            cols[name] = np.where(idx >= 0, angle, np.nan)
    take("allocation_status", ("thrust", "torque[0]", "torque[1]", "torque[2]", "saturated"),
         ("thrust", "tau_x", "tau_y", "tau_z", "saturated"))
    rotors = []
    motors = data.get("actuator_motors")
    if motors is not None:
        count = sum(1 for i in range(MAX_MOTORS) if not np.all(np.isnan(motors[f"control[{i}]"])))
        rotors = [f"omega_{i + 1}" for i in range(count)]
        take("actuator_motors", [f"control[{i}]" for i in range(count)], rotors)
    take("external_wrench_estimate", ("force[0]", "force[1]", "force[2]", "torque[0]", "torque[1]", "torque[2]",
                                      "mass"),
         ("fx_hat", "fy_hat", "fz_hat", "tx_hat", "ty_hat", "tz_hat", "mass_hat"))
    info = {key: ulog.msg_info_dict[name] for key, name in (("controller", "sys_controller"),
                                                           ("airframe", "sys_airframe"))
            if name in ulog.msg_info_dict}
    if take("external_wrench_truth", ("force[0]", "force[1]", "force[2]", "torque[0]", "torque[1]", "torque[2]"),
            ("fx_true", "fy_true", "fz_true", "tx_true", "ty_true", "tz_true")):
        truth = data["external_wrench_truth"]
        info["true_mass_kg"] = float(truth["mass"][-1])
        info["mass_mismatch_force_n"] = float(truth["mass_mismatch_force"][-1])
    return cols, rotors, info
