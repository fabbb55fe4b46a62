"""Draws docs/images/board_axes.png: a 4 x 3 board from `generate --board`,
seen tilted through a known camera, its pose from all its tags
(Detector.detect_board) and its frame drawn by chromatag.draw_board_pose.

    PYTHONPATH=build/python python3 scripts/board_figure.py docs/images/board_axes.png
"""
import json
import os
import sys
import tempfile

import cv2
import numpy as np

import chromatag


def main(out):
    with tempfile.TemporaryDirectory() as folder:
        page = os.path.join(folder, "board.png")
        chromatag.generate(page, board="4x3", size="20mm", page="150x130mm", dpi=300)
        board = chromatag.Board.from_file(page + ".json")
        origin = json.load(open(page + ".json"))["board"]["origin_mm"]
        image = cv2.imread(page)
    px_per_m = 300 / 0.0254
    board_from_px = np.array([[1 / px_per_m, 0, 0.5 / px_per_m - origin[0] / 1000],
                              [0, -1 / px_per_m, origin[1] / 1000 - 0.5 / px_per_m],
                              [0, 0, 1]])
    k = np.array([[900.0, 0, 400], [0, 900, 300], [0, 0, 1]])
    rotation = cv2.Rodrigues(np.array([np.pi, 0, 0]))[0] @ cv2.Rodrigues(
        np.array([0.45, -0.4, 0.1]))[0]
    translation = np.array([-0.06, 0.035, 0.3])
    h = k @ np.column_stack([rotation[:, 0], rotation[:, 1], translation]) @ board_from_px
    frame = cv2.warpPerspective(image, h, (800, 600), flags=cv2.INTER_AREA,
                                borderValue=(200, 200, 200))
    detector = chromatag.Detector(families=["16h5"], camera_matrix=k, dist_coeffs=[0] * 5)
    tags, pose = detector.detect_board(frame, board)
    if pose is None:
        sys.exit("board_figure: the board was not found")
    chromatag.draw_detections(frame, tags)
    chromatag.draw_board_pose(frame, pose, detector, axis_length=0.04)
    ends = cv2.projectPoints(0.04 * np.eye(3), pose.rvec, pose.tvec, k, None)[0].reshape(-1, 2)
    for name, end, colour in zip("xyz", ends, [(0, 0, 255), (0, 160, 0), (255, 0, 0)]):
        cv2.putText(frame, name, (int(end[0]) + 6, int(end[1]) - 6), cv2.FONT_HERSHEY_SIMPLEX,
                    0.8, colour, 2, cv2.LINE_AA)
    for row, text in enumerate(["board frame: origin at the bottom-left corner of the",
                                "bottom-left black square; x right, y up, z out of the page"]):
        cv2.putText(frame, text, (40, 540 + 25 * row), cv2.FONT_HERSHEY_SIMPLEX, 0.6,
                    (40, 40, 40), 1, cv2.LINE_AA)
    if not cv2.imwrite(out, frame):
        sys.exit(f"board_figure: cannot write {out}")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "docs/images/board_axes.png")
