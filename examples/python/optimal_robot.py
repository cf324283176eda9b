"""A URDF robot moved at least effort: the KUKA iiwa 14 (7 joints, read from its URDF file) from
rest at q = 0 to rest at a target in 2 s, its torques within the URDF's efforts and its joints
within their position and velocity limits, by the Simpson scheme's discrete mechanics and IPOPT;
then its flange sent to a pose instead. Checks what it can: the boundary states, the bounds, the
replay of the torques through the simulator, and the flange on its target.

    python3 examples/python/optimal_robot.py [OUT.png]
"""
import os
import sys

import numpy as np

import varsym

out = sys.argv[1] if len(sys.argv) > 1 else "iiwa_optimal.png"
here = os.path.dirname(os.path.abspath(__file__))
iiwa = varsym.Robot(os.path.join(here, "..", "..", "tests", "data", "urdf",
                                 "iiwa14_no_collision.urdf"))
target = [0.4, 0.3, 0.2, -0.3, 0.2, 0.3, 0.2]
move = varsym.optimize(iiwa, time=2.0, steps=50, q_start=np.zeros(7), q_end=target)
print(move)
limits = iiwa.limits
assert move.status == "solved"
assert np.allclose(move.q[-1], target, atol=1e-12) and np.allclose(move.v[-1], 0, atol=1e-8)
assert np.all(np.abs(move.u) <= limits["effort"] + 1e-6)              # the URDF's efforts
assert np.all((move.q >= limits["lower"] - 1e-9) & (move.q <= limits["upper"] + 1e-9))
assert move.closure < 1e-8                    # the simulator's replay of the torques
assert np.all(np.abs(move.v) <= limits["velocity"] * (1 + 1e-9))   # the URDF's velocities
reach = varsym.optimize(iiwa, time=2.0, steps=50, q_start=np.zeros(7), reach="iiwa_link_ee",
                        reach_position=[0.5, 0, 0.5], reach_rpy=[0, np.pi / 2, 0])
print(reach, "flange miss [m, rad]:", reach.reach_miss)
assert reach.reach_miss[0] < 1e-9 and reach.reach_miss[1] < 1e-7
move.coordinates = [name.replace("iiwa_", "") for name in move.coordinates]  # shorter legend
move.inputs = ["torque " + name for name in move.coordinates]
move.plot(out)
print("OK")
