"""
Hand-eye calibration and its residuals
======================================

A simulated six-axis arm shows its wrist camera a chessboard from 15 poses;
:func:`robostereo.robot.handeye.calibrate.calibrate_eye_in_hand` estimates the intrinsics
(OpenCV ``calibrateCamera``) and the flange-to-camera transform in closed form
(AX = XB, Park-Martin), checks the motion pairs' residuals against what the corner
noise can explain, and refines intrinsics, transform and board pose together on the
corners' reprojection.  The bars are each view's reprojection RMS after the
refinement; the title gives both estimates' error against the simulator's truth.
"""

import matplotlib.pyplot as plt
import numpy as np

from robostereo.robot.arms.sixaxis import WRIST_HAND_EYE
from robostereo.robot.handeye import calibrate_eye_in_hand
from robostereo.robot.simulated.sixaxis_handeye import simulate_handeye_views


def error(estimate):
    """Translation (mm) and rotation (deg) of ``estimate`` against the truth."""
    e = estimate.inv() @ WRIST_HAND_EYE
    return np.linalg.norm(e.translation), np.degrees(np.linalg.norm(e.rotvec))


views, truth = simulate_handeye_views(views=15, seed=0)
cal = calibrate_eye_in_hand(views.images, views.flange_poses, views.board,
                            pixel_pitch_mm=views.pixel_pitch_mm,
                            grey_levels=views.grey_levels)
closed, refined = error(cal.closed_form), error(cal.hand_eye)
print(f"closed form {closed[0]:.3f} mm, {closed[1]:.4f} deg; "
      f"refined {refined[0]:.3f} mm, {refined[1]:.4f} deg")

fig, ax = plt.subplots(figsize=(6.4, 3.6), layout="constrained")
ax.bar(np.arange(len(cal.per_view_rms_px)), cal.per_view_rms_px, color="0.3")
ax.set_xlabel("view")
ax.set_ylabel("reprojection RMS (px)")
ax.set_title(f"hand-eye error: closed form {closed[0]:.2f} mm, {closed[1]:.3f} deg; "
             f"refined {refined[0]:.2f} mm, {refined[1]:.3f} deg", fontsize=9)
plt.show()
