"""The figures of homework_study.py: Ex. 4's six estimator designs side by side and Ex. 5's errors,
inputs and final configuration. Builds matplotlib figures (no pyplot, no files); the caller saves
them inside plot_run.matplotlib_agg(). Values as logged: NED world, FRD body, SI units."""
import numpy as np

import plot_run

MAX_POINTS = 4000  # per line: min/max decimation keeps the oscillations' envelope
AXES = ("x", "y", "z")


def ex4_wrench(tests, series, truth, kind):
    """f̂ (kind 'force') or τ̂ (kind 'torque') of every design against time, one panel per design,
    x, y, z solid and the truth dashed in the same colour."""
    prefix, symbol, unit = ("f", "f", "N") if kind == "force" else ("t", "\\tau", "N·m")
    cols = 3
    rows = -(-len(tests) // cols)
    title = ("Estimated external force (world NED)" if kind == "force"
             else "Estimated external torque (body FRD)") + ", truth dashed"
    fig, axes = plot_run.new_figure(rows, cols, title=title, row_height=3.0)
    for k, (test, est) in enumerate(zip(tests, series)):
        ax = axes[k // cols, k % cols]
        for i, axis in enumerate(AXES):
            # x drawn wide and pale under y: in this flight the two often coincide.
            wide = {"linewidth": 3.5, "alpha": 0.45} if axis == "x" else {"linewidth": 1.2}
            plot_run.plot_line(ax, est["t"], est[prefix + axis], MAX_POINTS, color=f"C{i}",
                               label=f"$\\hat{{{symbol}}}_{axis}$", **wide)
            ax.step(truth["t"], truth[kind][:, i], where="post", color=f"C{i}", linestyle="--", linewidth=1,
                    label=f"${symbol}_{axis}$ true")
        ax.set_title(f"test {test['test']}: r = {test['order']}, {test['ripple_db']:g} dB, "
                     f"Wp = {test['wp_rad_s']:g} rad/s\n" + r"$\hat{f}_x$ settles: " + test["settling"],
                     fontsize="medium")
        if k % cols == 0:
            ax.set_ylabel(f"$\\hat{{{symbol}}}$ [{unit}]")
    for ax in axes.flat[len(tests):]:
        ax.set_visible(False)
    axes[0, 0].legend(loc="center right", fontsize="small", ncol=2)
    return fig


def mark(ax, t_end):
    """A dotted vertical line where the reference trajectory ends (if known)."""
    if t_end is not None:
        ax.axvline(t_end, color="0.4", linestyle=":", linewidth=1)


def stacked(t, values, title, labels, t_end):
    """Three stacked panels, one per column of values (N×3); the trajectory's end dotted."""
    fig, axes = plot_run.new_figure(3, title=title)
    for i, (ax, label) in enumerate(zip(axes[:, 0], labels)):
        plot_run.plot_line(ax, t, values[:, i], color=f"C{i}")
        mark(ax, t_end)
        ax.set_ylabel(label)
    return fig


def columns(topic, field):
    """field[0..3) of a topic as an N×3 array."""
    return np.column_stack([topic[f"{field}[{i}]"] for i in range(3)])


def ex5_figures(errors, alloc, weight, t_end):
    """Yields (file name, figure) for Ex. 5's errors, thrust and torques; t_end [s] (or None) is where
    the reference trajectory ends, dotted."""
    t = errors["t"]
    title_end = "" if t_end is None else f", the move ends at {t_end:g} s (dotted)"
    for name, field, symbol, unit, title in (
        ("position", "e_p", "e_p", "m", "Position error e_p = p − p_d (world NED)"),
        ("velocity", "e_v", "e_v", "m/s", "Velocity error e_v = ṗ − ṗ_d (world NED)"),
        ("attitude", "e_r", "e_R", "-", "Attitude error e_R = ½ vee(R_dᵀR − RᵀR_d) (body FRD)"),
        ("rate", "e_omega", "e_ω", "rad/s", "Angular-velocity error e_ω = ω − RᵀR_d ω_d (body FRD)"),
    ):
        yield f"ex5_{name}_errors.png", stacked(
            t, columns(errors, field), title + title_end, [f"{symbol},{a} [{unit}]" for a in AXES], t_end)
    fig, axes = plot_run.new_figure(1, title="Total thrust u_T" + title_end, row_height=3.5)
    ax = axes[0, 0]
    plot_run.plot_line(ax, alloc["t"], alloc["thrust"], label="u_T")
    mark(ax, t_end)
    ax.axhline(weight, color="black", linestyle="--", linewidth=1, label=f"m g = {weight:.5g} N")
    ax.set_ylabel("u_T [N]")
    ax.legend(loc="best", fontsize="small")
    yield "ex5_thrust.png", fig
    yield "ex5_torques.png", stacked(alloc["t"], columns(alloc, "torque"), "Body torques τ_b (FRD)" + title_end,
                                     [f"τ_{a} [N·m]" for a in AXES], t_end)


def rotation(q):
    """Rotation matrix body → world of the unit quaternion (w, x, y, z)."""
    w, x, y, z = np.asarray(q, dtype=np.float64) / np.linalg.norm(q)
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
        [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
        [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
    ])


def enu(ned):
    """Points (…×3, NED) in the right-handed display frame east, north, up."""
    ned = np.asarray(ned, dtype=np.float64)
    return np.stack([ned[..., 1], ned[..., 0], -ned[..., 2]], axis=-1)


def draw_vehicle(ax, p, r, hubs, spins, radius, axis_length=None):
    """Arms, rotor disks (CCW / CW seen from above) and, if axis_length, the body axes at pose (p, r)."""
    for k, (hub, spin) in enumerate(zip(hubs, spins)):
        arm = enu(np.array([p, p + r @ hub]))
        ax.plot(*arm.T, color="0.25", linewidth=2.5)
        if radius:
            theta = np.linspace(0, 2 * np.pi, 49)
            ring = hub + radius * np.outer(np.cos(theta), [1, 0, 0]) + radius * np.outer(np.sin(theta), [0, 1, 0])
            disk = enu(p + ring @ r.T)
            ax.plot(*disk.T, color="tab:purple" if spin > 0 else "tab:orange", linewidth=1.2,
                    label=("CCW rotor" if spin > 0 else "CW rotor") if axis_length and k < 2 else None)
    if axis_length:
        for i, (name, color) in enumerate((("x_b front", "tab:red"), ("y_b right", "tab:green"),
                                           ("z_b down", "tab:blue"))):
            start, tip = enu(p), enu(p + axis_length * r[:, i])
            ax.quiver(*start, *(tip - start), color=color, linewidth=2, arrow_length_ratio=0.15)
            ax.text(*tip, name, color=color, fontsize="small")


def label_enu(ax):
    """Axis labels of the east-north-up display frame in terms of the logged NED coordinates."""
    ax.set_xlabel("east = y_NED [m]")
    ax.set_ylabel("north = x_NED [m]")
    ax.set_zlabel("up = −z_NED [m]")


def ex5_final_configuration(p, reference, q, goal, hubs, spins, radius, final_error_m):
    """Left: the flown path (solid), the reference (dashed), start, goal and the vehicle at its final
    pose; right: a close-up of the final pose with the body axes and the final distance to the goal
    final_error_m [m]. Drawn east-north-up."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(13, 6.5), layout="constrained")
    fig.suptitle("Final configuration (drawn east-north-up; logged NED: up = −z)")
    r = rotation(q)
    final = p[-1]
    path, ref, goal_enu = enu(p[::10]), enu(reference), enu(goal)
    whole = fig.add_subplot(1, 2, 1, projection="3d")
    whole.plot(*path.T, color="C0", linewidth=1.5, label="flown path")
    whole.plot(*ref.T, color="black", linestyle="--", linewidth=1, label="reference")
    whole.scatter(*path[0], color="C2", s=40, label="start")
    whole.scatter(*goal_enu, color="gold", edgecolor="black", marker="*", s=250, label="goal")
    draw_vehicle(whole, final, r, hubs, spins, radius)
    whole.set_title("path")
    whole.set_aspect("equal")
    label_enu(whole)
    whole.legend(loc="upper left", fontsize="small")
    close = fig.add_subplot(1, 2, 2, projection="3d")
    reach = float(np.max(np.linalg.norm(hubs, axis=1))) + (radius or 0.0)
    draw_vehicle(close, final, r, hubs, spins, radius, axis_length=1.3 * reach)
    close.scatter(*goal_enu, color="gold", edgecolor="black", marker="*", s=250, label="goal", depthshade=False)
    centre = enu(final)
    span = 1.5 * reach
    close.set_xlim(centre[0] - span, centre[0] + span)
    close.set_ylim(centre[1] - span, centre[1] + span)
    close.set_zlim(centre[2] - span, centre[2] + span)
    close.set_aspect("equal")
    close.set_title(f"final pose at NED ({final[0]:.4f}, {final[1]:.4f}, {final[2]:.4f}) m, "
                    f"{final_error_m:.2e} m from the goal", fontsize="medium")
    label_enu(close)
    close.legend(loc="upper left", fontsize="small")
    return fig
