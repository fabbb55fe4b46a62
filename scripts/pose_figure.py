"""Draws docs/images/pose_axes.png: a tilted 16h5 tag rendered through a known
camera, detected with its pose, and its axes drawn by chromatag.draw_detections.

    PYTHONPATH=build/python python3 scripts/pose_figure.py docs/images/pose_axes.png
"""
import sys

import cv2
import numpy as np

import chromatag


def main(out):
    tag = chromatag.render_tag("16h5", 3, 40)  # Black square: pixels 80-319.
    k = np.array([[700.0, 0, 320], [0, 700, 240], [0, 0, 1]])
    metres_per_px = 0.06 / 240
    tag_from_px = np.array([[metres_per_px, 0, -199.5 * metres_per_px],
                            [0, -metres_per_px, 199.5 * metres_per_px], [0, 0, 1]])
    rotation = (cv2.Rodrigues(np.array([np.pi, 0, 0]))[0]
                @ cv2.Rodrigues(np.array([0.5, -0.45, 0.2]))[0])
    h = k @ np.column_stack([rotation[:, 0], rotation[:, 1], [0, 0, 0.32]]) @ tag_from_px
    frame = cv2.warpPerspective(tag, h, (640, 480), flags=cv2.INTER_AREA,
                                borderValue=(200, 200, 200))
    detector = chromatag.Detector(families=["16h5"], camera_matrix=k, dist_coeffs=[0] * 5,
                                  tag_size=0.06)
    tags = detector.detect(frame)
    chromatag.draw_detections(frame, tags, detector)
    pose = tags[0].pose
    ends = cv2.projectPoints(0.03 * np.eye(3), np.array(pose.rvec), np.array(pose.tvec), k,
                             None)[0].reshape(-1, 2)
    for name, end, colour in zip("xyz", ends, [(0, 0, 255), (0, 160, 0), (255, 0, 0)]):
        cv2.putText(frame, name, (int(end[0]) + 6, int(end[1]) - 6), cv2.FONT_HERSHEY_SIMPLEX,
                    0.8, colour, 2, cv2.LINE_AA)
    for row, text in enumerate(["tag frame: x right, y up, z towards the camera;",
                                "red dot: corner 0 (top-left of the upright tag)"]):
        cv2.putText(frame, text, (130, 420 + 25 * row), cv2.FONT_HERSHEY_SIMPLEX, 0.55,
                    (40, 40, 40), 1, cv2.LINE_AA)
    if not cv2.imwrite(out, frame[60:460, 110:560]):
        sys.exit(f"pose_figure: cannot write {out}")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "docs/images/pose_axes.png")
