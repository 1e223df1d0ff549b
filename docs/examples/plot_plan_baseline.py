"""
Plan the baseline for a depth accuracy
======================================

Eq. 9 of the thesis bounds the depth error by three terms: the baseline's and the
focal length's uncertainty, and the disparity's, which grows as ``Z^2 / (f D)``.
:func:`robostereo.robot.planning.baseline_plan.plan_baseline` inverts it: the baseline
``D`` whose bound at the target depth is the wanted accuracy.  Here, for the thesis's
camera, the baseline needed at each depth for 1, 2 and 5 mm.  Where a line stops, the plan is
refused: the disparity at the near end of the depth range would be wider than the
image (1 mm beyond about 1 m with this 509-pixel sensor).
"""

import matplotlib.pyplot as plt
import numpy as np

from robostereo.errors import InputError
from robostereo.geometry.camera import SEED_CAMERA
from robostereo.robot.planning import plan_baseline


def baseline(depth, accuracy):
    """The planned baseline (mm), NaN where no plan fits the image."""
    try:
        return plan_baseline(SEED_CAMERA, depth, accuracy).baseline_mm
    except InputError:
        return np.nan


depths = np.linspace(400.0, 1500.0, 45)
fig, ax = plt.subplots(figsize=(6.4, 4.0), layout="constrained")
for accuracy in (1.0, 2.0, 5.0):
    baselines = [baseline(z, accuracy) for z in depths]
    ax.plot(depths, baselines, label=f"{accuracy:g} mm")
plan = plan_baseline(SEED_CAMERA, 1000.0, 2.0)
ax.plot([plan.depth_mm], [plan.baseline_mm], "ko")
ax.annotate(f"D = {plan.baseline_mm:.0f} mm, search {plan.disparity_range[0]:.0f}.."
            f"{plan.disparity_range[1]:.0f} px", (plan.depth_mm, plan.baseline_mm),
            textcoords="offset points", xytext=(8, -14))
ax.set_xlabel("target depth Z (mm)")
ax.set_ylabel("baseline D (mm)")
ax.set_yscale("log")
ax.legend(title="eq. 9 bound")
plt.show()
