"""docs/python.md's examples, run as written: every ```python block of the page,
in order, in one namespace, in a folder holding the files the page assumes a
user has (a photo of a board through a camera, that camera's file, a
detector config from calibration, two scans of the printed sheet)."""
import contextlib
import io
import json
import os
import re

import numpy as np
import pytest

import chromatag

cv2 = pytest.importorskip("cv2")

DOCS = os.path.join(os.path.dirname(__file__), "..", "..", "docs", "python.md")
# The camera the page's examples name.
K = np.array([[1400.0, 0, 960], [0, 1400.0, 540], [0, 0, 1]])
D = np.array([-0.12, 0.05, 0, 0, 0])
SIZE = (1920, 1080)


def blocks():
    with open(DOCS) as f:
        return re.findall(r"^```python\n(.*?)^```$", f.read(), flags=re.S | re.M)


def photograph(page, dpi, K, D, size):
    """The page seen through the camera (K, D) from 0.3 m, turned a quarter
    (landscape) and tilted 20 and 15 degrees: every output pixel traced back
    through the distortion to the page's plane."""
    h, w = page.shape[:2]
    metres = 0.0254 / dpi
    R, _ = cv2.Rodrigues(np.array([np.radians(20), 0, 0]))
    R = R @ cv2.Rodrigues(np.array([0, np.radians(15), 0]))[0]
    R = R @ cv2.Rodrigues(np.array([0, 0, np.pi / 2]))[0]
    t = np.array([0, 0, 0.3])
    # Page pixels to normalised image coordinates, and back.
    H = np.column_stack([R[:, 0] * metres, R[:, 1] * metres,
                         t - (R[:, 0] * w + R[:, 1] * h) * metres / 2])
    back = np.linalg.inv(H)
    u, v = np.meshgrid(np.arange(size[0], dtype=np.float32), np.arange(size[1], dtype=np.float32))
    pixels = np.stack([u.ravel(), v.ravel()], axis=1).reshape(-1, 1, 2)
    normalised = cv2.undistortPoints(pixels, K, D).reshape(-1, 2).astype(np.float64)
    mapped = np.hstack([normalised, np.ones((normalised.shape[0], 1))]) @ back.T
    map_x = (mapped[:, 0] / mapped[:, 2]).reshape(size[1], size[0]).astype(np.float32)
    map_y = (mapped[:, 1] / mapped[:, 2]).reshape(size[1], size[0]).astype(np.float32)
    return cv2.remap(page, map_x, map_y, cv2.INTER_LINEAR, borderValue=(90, 100, 110))


@pytest.fixture
def user_files(tmp_path):
    # A photo of the board the page generates (board="6x4", the same layout).
    board_png = str(tmp_path / "printed_board.png")
    chromatag.generate(board_png, board="6x4", dpi=300)
    os.remove(board_png + ".json")
    photo = photograph(cv2.imread(board_png), 300, K, D, SIZE)
    os.remove(board_png)
    assert cv2.imwrite(str(tmp_path / "photo.jpg"), photo, [cv2.IMWRITE_JPEG_QUALITY, 92])
    # The camera's file, as OpenCV writes one.
    fs = cv2.FileStorage(str(tmp_path / "camera.yaml"), cv2.FILE_STORAGE_WRITE)
    fs.write("image_width", SIZE[0])
    fs.write("image_height", SIZE[1])
    fs.write("camera_matrix", K)
    fs.write("distortion_coefficients", D.reshape(1, 5))
    fs.release()
    # Thresholds as 'chromatag calibrate' writes them.
    with open(tmp_path / "detector.json", "w") as f:
        json.dump({"schema": "chromatag-detector-config", "schema_version": 1,
                   "options": {"adiff_thresh": 22.0, "border_thresh": 5.0,
                               "min_decision_margin": 2.0}}, f)
    # Two 300 dpi scans of the sheet the page generates (tags.pdf).
    ids = chromatag.family("16h5")["kept_ids"][:10]
    for name in ("scan1.png", "scan2.png"):
        chromatag.generate(str(tmp_path / name), family="16h5", ids=ids, size="40mm", page="a4",
                           dpi=300, label=True)
        os.remove(str(tmp_path / name) + ".json")
    return tmp_path


def test_every_python_example_of_the_page_runs_as_written(user_files, monkeypatch):
    code = blocks()
    assert len(code) >= 4
    monkeypatch.chdir(user_files)
    namespace = {"__name__": "docs_python_md"}
    out = io.StringIO()
    for i, block in enumerate(code):
        with contextlib.redirect_stdout(out):
            try:
                exec(compile(block, f"docs/python.md block {i + 1}", "exec"), namespace)
            except Exception as e:  # noqa: BLE001 - the block and the error, for the reader
                pytest.fail(f"docs/python.md block {i + 1} raised {type(e).__name__}: {e}\n{block}")
    # What the page says the examples give.
    assert namespace["tags"] and namespace["tags"][0].pose is not None
    assert namespace["pose"] is not None and len(namespace["pose"].tags_used) >= 20
    assert namespace["pose"].rms_error_px < 1.0, namespace["pose"].rms_error_px
    # The board is tilted as photographed: its normal 24.9 degrees off the optical axis.
    tilt = np.degrees(np.arccos(abs(namespace["pose"].rotation[2, 2])))
    assert abs(tilt - np.degrees(np.arccos(np.cos(np.radians(20)) * np.cos(np.radians(15))))) < 0.5, tilt
    assert namespace["verdict"].passed
    assert namespace["report"]["passed"], namespace["report"]
    assert len(namespace["pair"]) == 2
    assert "board.pdf" in os.listdir(user_files) and "tags.pdf.json" in os.listdir(user_files)
