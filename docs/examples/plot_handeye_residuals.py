"""
Hand-eye calibration and its residuals
======================================

A simulated six-axis arm shows its wrist camera a chessboard from 15 poses;
:func:`robostereo.robot.handeye.calibrate_eye_in_hand` estimates the intrinsics
(OpenCV ``calibrateCamera``) and the flange-to-camera transform (AX = XB).  The bars are
each view's reprojection RMS; the title gives the error against the simulator's truth.
"""

import matplotlib.pyplot as plt
import numpy as np

from robostereo.robot.handeye import calibrate_eye_in_hand
from robostereo.robot.simulated import simulate_handeye_views
from robostereo.robot.sixaxis import WRIST_HAND_EYE

views, truth = simulate_handeye_views(views=15, seed=0)
cal = calibrate_eye_in_hand(views.images, views.flange_poses, views.board,
                            pixel_pitch_mm=views.pixel_pitch_mm, grey_levels=views.grey_levels)
err = cal.hand_eye.inv() @ WRIST_HAND_EYE
print(f"hand-eye error {np.linalg.norm(err.translation):.3f} mm, "
      f"{np.degrees(np.linalg.norm(err.rotvec)):.3f} deg")

fig, ax = plt.subplots(figsize=(6.4, 3.6), layout="constrained")
ax.bar(np.arange(len(cal.per_view_rms_px)), cal.per_view_rms_px, color="0.3")
ax.set_xlabel("view")
ax.set_ylabel("reprojection RMS (px)")
ax.set_title(f"hand-eye error {np.linalg.norm(err.translation):.2f} mm, "
             f"{np.degrees(np.linalg.norm(err.rotvec)):.3f} deg")
plt.show()
