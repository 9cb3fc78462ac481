#!/usr/bin/python3
"""One RHex episode stepped by the `mujoco` Python package on qdmeta's own MJCF model (written by
`qdmeta-rhex-gait --mjcf FILE`): the GPU route of docs/scaling.md in its smallest form. The same
model and the same episode as the C++ engine (src/qdmeta/tasks/rhex/rhex_episode.cpp,
buehler_clock.cpp, rhex_mujoco_simulation.cpp): the Buehler clock and its PI servo on each hip
every 5 ms, split steps (mj_step2 then mj_step1), death by turning over after 2 s or by MuJoCo's
diverged warning, then unpowered settling until the pose is still; the distance is the body's
forward x displacement. tests/tools/test_rhex_mujoco_python.py compares it with the C++ engine.

Usage: tools/rhex_mujoco_episode.py MODEL.xml GENE,GENE,... (24 genes in [0, 1])
"""
import collections
import math
import sys

import numpy as np

GENE_STEP = 0.025                     # RhexParams::gene_step
KP, KI, INTEGRAL_LIMIT, TORQUE_LIMIT = 15.0, 15.0, math.pi, 4.0  # ServoParams
DURATION, TURNOVER_FROM = 5.0, 2.0    # EpisodeSettings
SETTLE_STEPS, STABLE_STEPS, STABLE_TOLERANCE = 1000, 30, 1e-4
LEGS = 6
# distance (m), dead, the body's position after each walking step, and the compliant legs' plate
# joint angles' range over the walk (rad; (0, 0) for rigid legs).
Episode = collections.namedtuple("Episode", "distance dead positions plate_range")


def decode_gait(genes):
    """Period, duty, stance angle, stance offset and phase offset per leg (decode_gait), the genes
    first snapped to the 0.025 grid and taken in single precision, as the C++ task stores them."""
    steps = round(1.0 / GENE_STEP)
    g = [min(max(round(float(np.float32(x)) * steps) / steps, 0.0), 1.0) for x in genes]
    period = 1.0 - 0.67 * g[0]
    return {"period": period, "duty": g[1:7], "stance": [math.pi * x for x in g[7:13]],
            "offset": [(x - 0.5) * math.pi / 2.0 for x in g[13:19]],
            "phase": [0.0] + [g[18 + i] * period / 2.0 for i in range(1, LEGS)]}


def target_angle(gait, leg, t):
    period = gait["period"]
    phase = t + gait["phase"][leg]
    cycles = math.floor(phase / period)
    tau = phase - cycles * period
    stance, t_stance = gait["stance"][leg], gait["duty"][leg] * period
    if t_stance > 0.0 and tau < t_stance:
        angle = -stance / 2.0 + (stance / t_stance) * tau
    elif period - t_stance > 0.0:
        angle = stance / 2.0 + ((2.0 * math.pi - stance) / (period - t_stance)) * (tau - t_stance)
    else:
        angle = stance / 2.0
    return angle + 2.0 * math.pi * cycles + gait["offset"][leg]


def euler_xyz(r):
    """Angles (x, y, z) of r = Rx Ry Rz."""
    return (-math.atan2(r[1, 2], r[2, 2]), math.asin(max(-1.0, min(1.0, r[0, 2]))), -math.atan2(r[0, 1], r[0, 0]))


def run_episode(model_xml, genes, passive_leg=None):
    """The Episode of `genes` on the model in `model_xml`; `passive_leg`: the leg whose hip turns
    freely (passive-hip damage), never driven."""
    import mujoco
    m = mujoco.MjModel.from_xml_string(model_xml)
    d = mujoco.MjData(m)
    dt = m.opt.timestep
    body = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, "body")
    hips = [mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_JOINT, f"hip_{i}") for i in range(LEGS)]
    gait = decode_gait(genes)
    turns, integral, positions, plate_range = [0] * LEGS, [0.0] * LEGS, [], [0.0, 0.0]
    names = [mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_JOINT, j) or "" for j in range(m.njnt)]
    plates = [m.jnt_qposadr[j] for j, name in enumerate(names) if "_joint_" in name]  # leg_I_joint_K

    def pose():
        return d.xpos[body].copy(), d.xmat[body].reshape(3, 3).copy()

    def relative(start, now):
        return tuple(now[0] - start[0]) + euler_xyz(start[1].T @ now[1])

    def diverged():
        return d.warning[mujoco.mjtWarning.mjWARN_BADQACC].number > 0

    def step():
        mujoco.mj_step2(m, d)
        mujoco.mj_step1(m, d)

    mujoco.mj_step1(m, d)
    start = pose()
    # A blocked hip has no joint, a removed leg no hip: neither has a servo; nor has a passive hip.
    for step_index in range(round(DURATION / dt)):
        t = step_index * dt
        for i, j in enumerate(hips):
            if j < 0 or i == passive_leg:
                continue
            q = d.qpos[m.jnt_qposadr[j]]
            target = target_angle(gait, i, t)
            while target - 2.0 * math.pi * turns[i] - q >= 2.0 * math.pi:
                turns[i] += 1
            target -= 2.0 * math.pi * turns[i]
            if q - target > 1.5 * math.pi:
                target += 2.0 * math.pi
            error = target - q
            integral[i] = min(max(integral[i] + error * dt, -INTEGRAL_LIMIT), INTEGRAL_LIMIT)
            d.qfrc_applied[m.jnt_dofadr[j]] = min(max(KP * error + KI * integral[i], -TORQUE_LIMIT), TORQUE_LIMIT)
        step()
        positions.append(pose()[0])
        if plates:
            plate_range = [min(plate_range[0], d.qpos[plates].min()), max(plate_range[1], d.qpos[plates].max())]
        if step_index + 1 >= round(TURNOVER_FROM / dt) and pose()[1][2, 2] <= 0.0:
            return Episode(relative(start, pose())[0], True, positions, tuple(plate_range))
        if diverged():
            return Episode(relative(start, pose())[0], True, positions, tuple(plate_range))
    for j in hips:
        if j >= 0:
            d.qfrc_applied[m.jnt_dofadr[j]] = 0.0
    last, quiet = relative(start, pose()), 0
    for _ in range(SETTLE_STEPS):
        step()
        if diverged():
            return Episode(relative(start, pose())[0], True, positions, tuple(plate_range))
        now = relative(start, pose())
        change = math.sqrt(sum((a - b) ** 2 for a, b in zip(now, last)))
        last = now
        quiet = quiet + 1 if change < STABLE_TOLERANCE else 0
        if quiet > STABLE_STEPS:
            return Episode(now[0], False, positions, tuple(plate_range))
    return Episode(last[0], True, positions, tuple(plate_range))


if __name__ == "__main__":
    with open(sys.argv[1]) as f:
        e = run_episode(f.read(), [float(x) for x in sys.argv[2].split(",")])
    print(f"distance {e.distance:.9g} m{' (dead)' if e.dead else ''}, plate joints over the walk "
          f"[{e.plate_range[0]:.3g}, {e.plate_range[1]:.3g}] rad")
