"""The Python module against the library's own tags and sheets."""
import copy as copy_module
import json
import os
import pickle
import threading
import warnings

import numpy as np
import pytest

import chromatag

cv2 = pytest.importorskip("cv2")


def scene(family="16h5", tag_id=3, cell_px=12, at=(60, 50), size=(400, 480), palette="default"):
    """A tag pasted on a mid-grey frame; returns the frame and the black square's
    top-left corner in pixel-centre coordinates."""
    tag = chromatag.render_tag(family, tag_id, cell_px, palette=palette)
    frame = np.full((size[0], size[1], 3), 128, np.uint8)
    x, y = at
    frame[y:y + tag.shape[0], x:x + tag.shape[1]] = tag
    quiet = 2 * cell_px
    return frame, (x + quiet - 0.5, y + quiet - 0.5)


def test_detects_a_rendered_tag_with_its_corners():
    frame, top_left = scene()
    detections = chromatag.Detector().detect(frame)
    assert len(detections) == 1
    tag = detections[0]
    assert (tag.family, tag.id, tag.hamming) == ("16h5", 3, 0)
    assert tag.corners.shape == (4, 2) and tag.corners.dtype == np.float64
    side = 6 * 12  # 16h5: a black square of 6 cells.
    expected = np.array(top_left) + np.array([[0, 0], [side, 0], [side, side], [0, side]])
    np.testing.assert_allclose(tag.corners, expected, atol=0.5)
    assert tag.decision_margin > 2
    assert tag.pose is None
    np.testing.assert_allclose(tag.center, expected.mean(axis=0), atol=0.5)


def test_both_families_by_default_and_rgb_order():
    frame, _ = scene("36h11", 7, cell_px=10)
    detector = chromatag.Detector()
    assert detector.families == ["16h5", "36h11"]
    bgr = detector.detect(frame)
    rgb = detector.detect(np.ascontiguousarray(frame[:, :, ::-1]), order="rgb")
    assert [(d.family, d.id) for d in bgr] == [("36h11", 7)]
    np.testing.assert_allclose(rgb[0].corners, bgr[0].corners)
    # Read with the wrong order, red and blue swap and nothing is a tag.
    with pytest.warns(UserWarning, match="order='bgr'"):
        assert detector.detect(frame, order="rgb") == []
    assert chromatag.Detector("16h5").detect(frame) == []


def test_a_frame_with_swapped_colours_is_said_once():
    frame, _ = scene("16h5", 3)
    rgb = np.ascontiguousarray(frame[:, :, ::-1])
    detector = chromatag.Detector()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        assert detector.detect(rgb) == []  # The result is not changed, only named.
        assert detector.detect(rgb) == []
        assert len(detector.detect(rgb, order="rgb")) == 1
        assert detector.detect(np.full_like(frame, 128)) == []
    assert len(caught) == 1, [str(w.message) for w in caught]
    message = str(caught[0].message)
    assert "no tag found with order='bgr', but 1 with order='rgb'" in message
    assert "Pass order='rgb'" in message
    # A tag-free stream is checked only at its start: the 17th empty frame is
    # detected once (the check would find the same nothing).
    quiet = chromatag.Detector()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        for _ in range(20):
            quiet.detect(np.full_like(frame, 90))
        assert quiet.detect(rgb) == []  # Past the checks: no second detection, no warning.
    assert caught == []
    # Warnings turned into errors raise from detect.
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(UserWarning):
            chromatag.Detector().detect(rgb)


def test_views_and_four_channels_are_accepted():
    frame, _ = scene()
    big = np.zeros((frame.shape[0], frame.shape[1] * 2, 3), np.uint8)
    big[:, ::2] = frame  # A strided view: not contiguous.
    assert [d.id for d in chromatag.Detector().detect(big[:, ::2])] == [3]
    bgra = np.dstack([frame, np.full(frame.shape[:2], 255, np.uint8)])
    assert [d.id for d in chromatag.Detector().detect(bgra)] == [3]


@pytest.mark.parametrize(
    "image, message",
    [
        (np.zeros((50, 50), np.uint8), "colour image"),
        (np.zeros((50, 50, 3), np.float32), "8-bit"),
        (np.zeros((50, 50, 2), np.uint8), "H x W x 3"),
    ],
)
def test_bad_images_raise(image, message):
    with pytest.raises(chromatag.Error, match=message):
        chromatag.Detector().detect(image)


def test_bad_options_raise_value_errors():
    with pytest.raises(ValueError, match="unknown option"):
        chromatag.Detector(stepp=3)
    with pytest.raises(ValueError, match="step"):
        chromatag.Detector(step=0)
    with pytest.raises(ValueError, match="unknown family"):
        chromatag.Detector("25h9")
    with pytest.raises(ValueError, match="camera_matrix"):
        chromatag.Detector(tag_size=0.05)
    with pytest.raises(ValueError, match="pixel order"):
        chromatag.Detector().detect(scene()[0], order="bgra")


def test_small_inputs_refuse_huge_views_before_copying():
    # 2**31 elements that cost no memory as a view and 16 GB as doubles.
    huge = np.broadcast_to(np.zeros((1,), np.uint8), (4096, 4096, 128))
    k = np.array([[500.0, 0, 240], [0, 500.0, 200], [0, 0, 1]])
    with pytest.raises(ValueError, match="camera_matrix must be 3 x 3"):
        chromatag.Detector(camera_matrix=huge)
    with pytest.raises(ValueError, match="dist_coeffs must be numbers"):
        chromatag.Detector(camera_matrix=k, dist_coeffs=huge)
    with pytest.raises(ValueError, match="position must be 3 numbers"):
        chromatag.BoardTag("16h5", 0, 0.03, huge)
    with pytest.raises(ValueError, match="rotation must be 3 x 3"):
        chromatag.BoardTag("16h5", 0, 0.03, [0.0, 0.0, 0.0], huge)
    # A strided (reversed) view is read in its own order.
    reversed_k = np.ascontiguousarray(k[::-1, ::-1])[::-1, ::-1]
    tag = chromatag.BoardTag("16h5", 0, 0.03, np.array([3.0, 2.0, 1.0])[::-1])
    assert list(tag.position) == [1.0, 2.0, 3.0]
    chromatag.Detector(camera_matrix=reversed_k, dist_coeffs=np.array([0.0, 0, 0, 0.1])[::-1])


def test_a_camera_matrix_of_another_shape_is_refused_naming_the_entry():
    k = np.array([[500.0, 0, 240], [0, 500.0, 200], [0, 0, 1]])
    with pytest.raises(ValueError, match=r"entry \[2\]\[0\] is 240, not 0: is the matrix transposed"):
        chromatag.Detector(camera_matrix=k.T)
    skewed = k.copy()
    skewed[0, 1] = 0.5
    with pytest.raises(ValueError, match=r"entry \[0\]\[1\] is 0.5, a skew"):
        chromatag.Detector(camera_matrix=skewed)
    corner = k.copy()
    corner[2, 2] = 0
    with pytest.raises(ValueError, match=r"entry \[2\]\[2\] is 0, not 1"):
        chromatag.Detector(camera_matrix=corner)


def test_pose_from_camera_and_tag_size():
    frame, _ = scene(cell_px=12)
    f = 500.0
    k = np.array([[f, 0, 240], [0, f, 200], [0, 0, 1]])
    detector = chromatag.Detector(camera_matrix=k, tag_size=0.06)
    tag = detector.detect(frame)[0]
    # A fronto-parallel tag of 72 px: depth f * size / pixels.
    assert tag.pose.tvec[2] == pytest.approx(f * 0.06 / 72, rel=0.02)
    np.testing.assert_allclose(tag.pose.rotation @ tag.pose.rotation.T, np.eye(3), atol=1e-9)
    before = frame.copy()
    assert chromatag.draw_detections(frame, [tag], detector) is frame
    assert (frame != before).any(axis=2).sum() > 200


def test_pose_filter_smooths_a_still_tag_through_noise():
    frame, _ = scene(cell_px=8)
    k = np.array([[500.0, 0, 240], [0, 500.0, 200], [0, 0, 1]])
    detector = chromatag.Detector(camera_matrix=k, tag_size=0.06)
    rng = np.random.default_rng(5)
    smoother = chromatag.PoseFilter()
    assert not smoother.started
    raw, filtered = [], []
    for i in range(40):
        noisy = np.clip(frame + rng.normal(0, 14, frame.shape), 0, 255).astype(np.uint8)
        tags = detector.detect(noisy)
        assert len(tags) == 1
        out = smoother.update(i / 30.0, tags[0].pose)
        assert isinstance(out, chromatag.FilteredPose) and out.used
        assert out.restarted == (i == 0)
        assert out.covariance.shape == (6, 6) and out.rotation.shape == (3, 3)
        if i >= 10:  # The filter settling.
            raw.append(tags[0].pose.tvec[2])
            filtered.append(out.tvec[2])
    assert smoother.started
    for protocol in range(pickle.HIGHEST_PROTOCOL + 1):
        with pytest.raises(TypeError, match="cannot pickle 'PoseFilter' object"):
            pickle.dumps(smoother, protocol=protocol)
    # The tag does not move: the filtered distance wanders less than each frame's own.
    assert np.std(filtered) < 0.8 * np.std(raw)
    assert abs(np.mean(filtered) - np.mean(raw)) < 3 * np.std(raw)
    smoother.reset()
    assert not smoother.started


def test_pose_filter_refuses_bad_options_and_poses():
    with pytest.raises(chromatag.Error, match="acceleration"):
        chromatag.PoseFilter(rotation_acceleration=-1)
    with pytest.raises(chromatag.Error, match="pose must be a chromatag.Pose or a chromatag.BoardPose"):
        chromatag.PoseFilter().update(0.0, [0, 0, 1])


def test_detection_compares_pickles_and_reads_as_the_cli_json():
    frame, _ = scene(cell_px=12)
    k = np.array([[500.0, 0, 240], [0, 500.0, 200], [0, 0, 1]])
    tag = chromatag.Detector(camera_matrix=k, tag_size=0.06).detect(frame)[0]
    again = chromatag.Detector(camera_matrix=k, tag_size=0.06).detect(frame)[0]
    assert tag == again and hash(tag) == hash(again) and tag != "tag"
    copy = pickle.loads(pickle.dumps(tag))
    assert copy == tag and copy.as_dict() == tag.as_dict()
    np.testing.assert_array_equal(copy.homography, tag.homography)
    d = tag.as_dict()
    assert set(d) == {"family", "id", "hamming", "margin", "corners", "green_corners",
                      "red_corners", "pose"}
    assert set(d["pose"]) == {"rvec", "tvec", "rms_error_px", "ambiguity", "covariance"}
    # ROS's 36 numbers, row-major, as the pose's 6 x 6 matrix; pickles keep
    # both covariances.
    np.testing.assert_array_equal(np.array(d["pose"]["covariance"]).reshape(6, 6),
                                  tag.pose.covariance)
    np.testing.assert_array_equal(copy.pose.covariance, tag.pose.covariance)
    np.testing.assert_array_equal(copy.corner_covariance, tag.corner_covariance)
    assert tag.corner_covariance.shape == (8, 8) and (np.diag(tag.corner_covariance) > 0).all()
    assert d["margin"] == tag.decision_margin
    np.testing.assert_allclose(np.array(d["green_corners"]), tag.green_corners)
    # The green ring lies one cell (12 px) inside the black square.
    np.testing.assert_allclose(tag.green_corners[0] - tag.corners[0], [12, 12], atol=0.5)
    assert "id=3" in repr(tag) and "center=" in repr(tag)
    # Lists, not tuples: equal to what json.loads gives for the CLI's line.
    assert json.loads(json.dumps(d)) == d
    with pytest.raises(chromatag.Error, match="not a pickled"):
        chromatag.Detection.__new__(chromatag.Detection).__setstate__(("16h5", 99, 0, False, []))


def test_pickling_works_or_raises_type_error_at_every_protocol():
    # Protocols 0 and 1 build objects through copyreg, which aborted the
    # interpreter on every class of the module.
    frame, _ = scene(cell_px=12)
    tag = chromatag.Detector().detect(frame)[0]
    board = chromatag.Board("b", [chromatag.BoardTag("16h5", 0, 0.03, [0, 0, 0]),
                                  chromatag.BoardTag("16h5", 1, 0.03, [0.05, 0, 0],
                                                     np.eye(3)[[1, 0, 2]] * [1, -1, 1])])
    for protocol in range(pickle.HIGHEST_PROTOCOL + 1):
        assert pickle.loads(pickle.dumps(tag, protocol=protocol)) == tag
        copy = pickle.loads(pickle.dumps(board, protocol=protocol))
        assert copy.name == "b" and len(copy) == 2
        np.testing.assert_array_equal(copy.tags[1].rotation, board.tags[1].rotation)
        np.testing.assert_array_equal(copy.tags[1].position, [0.05, 0, 0])
        with pytest.raises(TypeError, match="cannot pickle 'Detector' object: build a Detector"):
            pickle.dumps(chromatag.Detector(), protocol=protocol)
    assert copy_module.deepcopy(board).tags[0].id == 0
    with pytest.raises(TypeError, match="cannot pickle 'Detector'"):
        chromatag.Detector().__reduce__()
    with pytest.raises(chromatag.Error, match="not a pickled chromatag.Board"):
        chromatag.Board.__new__(chromatag.Board).__setstate__(("b", "", [("16h5", 0, 0.03, [0, 0], [])]))


def test_pupil_apriltags_call_shape():
    frame, _ = scene(cell_px=12)
    f = 500.0
    k = np.array([[f, 0, 240], [0, f, 200], [0, 0, 1]])
    built = chromatag.Detector(camera_matrix=k, tag_size=0.06).detect(frame)[0]
    detector = chromatag.Detector()
    per_call = detector.detect(frame, estimate_tag_pose=True, camera_params=(f, f, 240, 200),
                               tag_size=0.06)[0]
    np.testing.assert_allclose(per_call.pose.tvec, built.pose.tvec, rtol=1e-9)
    assert detector.detect(frame)[0].pose is None  # Only for that call.
    with pytest.raises(chromatag.Error, match="estimate_tag_pose needs"):
        detector.detect(frame, estimate_tag_pose=True)
    with pytest.raises(chromatag.Error, match="for estimate_tag_pose=True"):
        detector.detect(frame, tag_size=0.06)


def test_what_is_not_an_image_is_named():
    detector = chromatag.Detector()
    with pytest.raises(chromatag.Error, match="cv2.imread"):
        detector.detect(None)
    with pytest.raises(chromatag.Error, match="numpy array"):
        detector.detect([[1, 2, 3]])


def test_camera_from_a_file_and_the_fisheye_model(tmp_path):
    frame, _ = scene(cell_px=12)
    f = 500.0
    k = np.array([[f, 0, 240], [0, f, 200], [0, 0, 1]])
    # The camera file calibrate-camera writes (ROS camera_info layout) gives
    # the same pose as the matrix given by hand.
    path = tmp_path / "camera.yaml"
    path.write_text("image_width: 480\nimage_height: 400\ncamera_name: camera\n"
                    "camera_matrix:\n  rows: 3\n  cols: 3\n  data: [500, 0, 240, 0, 500, 200, 0, 0, 1]\n"
                    "distortion_model: equidistant\n"
                    "distortion_coefficients:\n  rows: 1\n  cols: 4\n  data: [0.1, 0, 0, 0]\n")
    from_file = chromatag.Detector(camera_file=str(path), tag_size=0.06).detect(frame)[0]
    by_hand = chromatag.Detector(camera_matrix=k, dist_coeffs=[0.1, 0, 0, 0], camera_model="fisheye",
                                 tag_size=0.06).detect(frame)[0]
    np.testing.assert_allclose(from_file.pose.tvec, by_hand.pose.tvec, rtol=1e-12)
    pinhole = chromatag.Detector(camera_matrix=k, dist_coeffs=[0.1, 0, 0, 0],
                                 tag_size=0.06).detect(frame)[0]
    assert abs(pinhole.pose.tvec[2] - by_hand.pose.tvec[2]) > 1e-6  # The model matters.
    with pytest.raises(chromatag.Error, match="fisheye model needs 4"):
        chromatag.Detector(camera_matrix=k, dist_coeffs=[0.1] * 5, camera_model="fisheye")
    with pytest.raises(chromatag.Error, match="camera_model must be"):
        chromatag.Detector(camera_matrix=k, camera_model="omni")
    with pytest.raises(chromatag.Error, match="not both"):
        chromatag.Detector(camera_matrix=k, camera_file=str(path))
    with pytest.raises(chromatag.Error, match="camera_model comes from camera_file"):
        chromatag.Detector(camera_file=str(path), camera_model="fisheye")
    with pytest.raises(chromatag.Error, match="missing.yaml"):
        chromatag.Detector(camera_file=str(tmp_path / "missing.yaml"))
    # The file's intrinsics, as OpenCV's functions take them.
    camera = chromatag.read_camera(str(path))
    np.testing.assert_array_equal(camera["camera_matrix"], k)
    np.testing.assert_array_equal(camera["dist_coeffs"], [0.1, 0, 0, 0])
    assert camera["camera_model"] == "fisheye"
    assert camera["image_size"] == (480, 400)
    assert sorted(camera) == ["camera_matrix", "camera_model", "dist_coeffs", "image_size"]
    with pytest.raises(chromatag.Error, match="missing.yaml"):
        chromatag.read_camera(str(tmp_path / "missing.yaml"))


def test_one_default_family_set_and_one_table_of_option_names():
    # Both families, as in C++ and the CLI.
    assert chromatag.Detector().families == ["16h5", "36h11"]
    assert chromatag.Detector(row_step=5, two_step_rises=True).families == ["16h5", "36h11"]
    # The benchmarks' switches are not options; the error lists the names.
    with pytest.raises(chromatag.Error, match="unknown option \"grow_regions\".*row_step"):
        chromatag.Detector(grow_regions=False)


def test_white_balance_is_an_option_of_three_gains(tmp_path):
    # A green cast in linear light (red and blue at 0.6 of green), undone by
    # the gains that a calibration would write.
    frame, _ = scene(palette="iccv17")
    v = frame / 255.0
    linear = np.where(v <= 0.04045, v / 12.92, ((v + 0.055) / 1.055) ** 2.4)
    linear[..., 0] *= 0.6  # B (the frame is BGR)
    linear[..., 2] *= 0.6  # R
    cast = np.where(linear <= 0.0031308, 12.92 * linear, 1.055 * linear ** (1 / 2.4) - 0.055)
    cast = np.round(255 * cast).astype(np.uint8)
    detections = chromatag.Detector(white_balance=(1.0, 0.6, 1.0)).detect(cast)
    assert [(d.family, d.id) for d in detections] == [("16h5", 3)]
    config = tmp_path / "detector.json"
    config.write_text(json.dumps({"schema": "chromatag-detector-config", "schema_version": 1,
                                  "options": {"white_balance": [1.0, 0.6, 1.0]}}))
    assert len(chromatag.Detector(config=str(config)).detect(cast)) == 1
    with pytest.raises(chromatag.Error, match="largest gain must be 1; divide all three by it"):
        chromatag.Detector(white_balance=[1.5, 1.0, 1.5])
    with pytest.raises(chromatag.Error, match="list of three numbers"):
        chromatag.Detector(white_balance=0.8)


@pytest.mark.parametrize("offset_m", [0.0, 0.01])
@pytest.mark.parametrize("quarter_turns", [0, 1, 2, 3])
def test_pose_of_an_exactly_frontal_tag(offset_m, quarter_turns):
    # A noise-free render facing the camera at 0.5 m: camera_from_tag turns
    # 180 degrees about x, where a Rodrigues vector is singular.
    tag = chromatag.render_tag("16h5", 3, 60)  # Black square: pixels 120-479.
    k = np.array([[600.0, 0, 376], [0, 600, 240], [0, 0, 1]])
    metres_per_px = 0.06 / 360
    tag_from_px = np.array([[metres_per_px, 0, -299.5 * metres_per_px],
                            [0, -metres_per_px, 299.5 * metres_per_px], [0, 0, 1]])
    rotation = (cv2.Rodrigues(np.array([np.pi, 0, 0]))[0]
                @ cv2.Rodrigues(np.array([0, 0, quarter_turns * np.pi / 2]))[0])
    translation = np.array([offset_m, 0, 0.5])
    h = k @ np.column_stack([rotation[:, 0], rotation[:, 1], translation]) @ tag_from_px
    frame = cv2.warpPerspective(tag, h, (752, 480), flags=cv2.INTER_AREA,
                                borderValue=(255, 255, 255))
    detector = chromatag.Detector(families=["16h5"], camera_matrix=k, dist_coeffs=[0] * 5,
                                  tag_size=0.06)
    pose = detector.detect(frame)[0].pose
    assert np.isfinite(pose.rvec).all() and np.isfinite(pose.tvec).all()
    assert np.linalg.norm(pose.rvec) <= np.pi + 1e-9
    error = cv2.Rodrigues(pose.rotation.T @ rotation)[0]
    assert np.degrees(np.linalg.norm(error)) < 0.5
    assert np.linalg.norm(pose.tvec - translation) < 0.005 * 0.5
    assert pose.ambiguity == 0.0  # Both planar solutions refine to this one.
    # The covariance: symmetric, positive definite, and the errors against
    # the truth within four of its standard deviations on every axis.
    c = pose.covariance
    assert c.shape == (6, 6)
    np.testing.assert_allclose(c, c.T, rtol=1e-9, atol=1e-18)
    assert (np.linalg.eigvalsh(c) > 0).all()
    w = cv2.Rodrigues(rotation @ pose.rotation.T)[0].ravel()
    assert (np.abs(np.concatenate([translation - pose.tvec, w])) < 4 * np.sqrt(np.diag(c))).all()


def test_rejected_candidates_on_request():
    frame, _ = scene()
    frame[300:360, 300:360] = (40, 40, 220)  # A red square: no tag.
    detector = chromatag.Detector(report_rejected=True)
    detections, rejected = detector.detect(frame, return_rejected=True)
    assert [d.id for d in detections] == [3]
    assert rejected and all({"stage", "reason", "outline"} <= set(r) for r in rejected)


def test_a_generated_page_read_with_cv2(tmp_path):
    page = str(tmp_path / "sheet.png")
    written = chromatag.generate(page, ids=[0, 4, 9], size="30mm", dpi=150)
    assert written == [page, page + ".json"]
    sidecar = json.load(open(page + ".json"))
    found = chromatag.Detector().detect(cv2.imread(page))
    assert sorted(d.id for d in found) == sorted(t["id"] for t in sidecar["tags"])


def test_generate_and_verify(tmp_path):
    sheet = str(tmp_path / "tags.pdf")
    chromatag.generate(sheet, family="36h11", ids="0-3", size="30mm")
    verdict = chromatag.verify(sheet)
    assert verdict.passed and verdict.tags_passed == 4
    assert [t.found_id for t in verdict.tags] == [0, 1, 2, 3]
    with pytest.raises(chromatag.Error, match="format is png"):
        chromatag.generate(str(tmp_path / "x.pdf"), ids=[0], format="png")
    with pytest.raises(chromatag.Error, match="no such file"):
        chromatag.verify(str(tmp_path / "missing.pdf"))
    assert not os.path.exists(tmp_path / "x.pdf")


def test_verify_print(tmp_path):
    # A PNG sheet records its 300 dpi: as a "scan" it is a perfect print.
    page = str(tmp_path / "page.png")
    chromatag.generate(page, family="16h5", ids="0-3", size="30mm", format="png")
    verdict = chromatag.verify_print(page, [page], scans=True)
    assert verdict["passed"] and verdict["tags_passed"] == 4
    assert abs(verdict["images"][0]["scale"]["x"] - 1.0) < 0.002
    # Shrunk to 97 % on a white page of the same size: fails, naming the scale.
    image = cv2.imread(page)
    small = cv2.resize(image, None, fx=0.97, fy=0.97, interpolation=cv2.INTER_AREA)
    canvas = np.full_like(image, 255)
    canvas[: small.shape[0], : small.shape[1]] = small
    shrunk = str(tmp_path / "shrunk.png")
    cv2.imwrite(shrunk, canvas)
    verdict = chromatag.verify_print(page + ".json", [shrunk], scan_dpi=300)
    assert not verdict["passed"]
    assert abs(verdict["images"][0]["scale"]["y"] - 0.97) < 0.002
    assert "printed at 97.0 %" in verdict["images"][0]["problems"][0]
    with pytest.raises(chromatag.Error, match="does not record its resolution"):
        chromatag.verify_print(page, [shrunk], scans=True)


def test_threads_share_one_detector():
    frames = [scene(tag_id=i)[0] for i in (0, 1, 2, 3)]
    detector = chromatag.Detector()
    results = {}

    def run(i):
        for _ in range(20):
            results[i] = [d.id for d in detector.detect(frames[i])]

    threads = [threading.Thread(target=run, args=(i,)) for i in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert results == {0: [0], 1: [1], 2: [2], 3: [3]}


def test_families_and_palettes():
    assert chromatag.families() == ["16h5", "36h11"]
    info = chromatag.family("16h5")
    assert info["black_square_cells"] == 6 and 3 in info["kept_ids"]
    shades = chromatag.palette("default")["shades"]
    assert set(shades) == {"red-1", "red-0", "green-1", "green-0", "black", "white"}
    assert shades["red-1"]["lab"][1] > 40 > shades["green-1"]["lab"][1]
    assert chromatag.render_tag("16h5", 3, 5, order="rgb").shape == (50, 50, 3)
    with pytest.raises(chromatag.Error):
        chromatag.render_tag("16h5", 10000, 5)


def test_board_pose_from_a_generated_board(tmp_path):
    # generate(board=...) writes the board file beside the page; the page is
    # warped into a tilted view whose pose is known.
    page = str(tmp_path / "board.png")
    chromatag.generate(page, board="4x3", size="20mm", page="180x140mm", dpi=200)
    board = chromatag.Board.from_file(page + ".json")
    assert len(board) == 12 and board.name == "board.png" and board.palette == "default"
    sidecar = json.load(open(page + ".json"))
    origin = sidecar["board"]["origin_mm"]
    image = cv2.imread(page)
    px_per_m = 200 / 0.0254
    # Page pixel centres to board metres: x right, y up from the origin.
    board_from_px = np.array([[1 / px_per_m, 0, 0.5 / px_per_m - origin[0] / 1000],
                              [0, -1 / px_per_m, origin[1] / 1000 - 0.5 / px_per_m],
                              [0, 0, 1]])
    k = np.array([[900.0, 0, 640], [0, 900, 480], [0, 0, 1]])
    rotation = cv2.Rodrigues(np.array([2.8, 0.3, -0.2]))[0]
    translation = np.array([-0.05, 0.03, 0.4])
    h = k @ np.column_stack([rotation[:, 0], rotation[:, 1], translation]) @ board_from_px
    frame = cv2.warpPerspective(image, h, (1280, 960), flags=cv2.INTER_AREA,
                                borderValue=(120, 110, 100))
    detector = chromatag.Detector(families=["16h5"], camera_matrix=k)
    detections, pose = detector.detect_board(frame, board)
    assert len(detections) == 12
    assert sorted(pose.tags_used) == sorted(t.id for t in board.tags)
    assert pose.tags_rejected == []
    error = cv2.Rodrigues(pose.rotation.T @ rotation)[0]
    assert np.degrees(np.linalg.norm(error)) < 0.2
    assert np.linalg.norm(pose.tvec - translation) < 0.002 * 0.4
    drawn = chromatag.draw_board_pose(frame.copy(), pose, detector, axis_length=0.05)
    assert (drawn != frame).any()
    # No board tag in view: the detections, and None.
    blank = np.full((480, 640, 3), 200, np.uint8)
    assert detector.detect_board(blank, board) == ([], None)
    # Without intrinsics there is no pose to give.
    with pytest.raises(chromatag.Error, match="camera_matrix"):
        chromatag.Detector().detect_board(frame, board)


def test_boards_built_by_hand_and_from_a_bundle_file(tmp_path):
    board = chromatag.Board("pair", [chromatag.BoardTag("16h5", 1, 0.05, [0, 0, 0]),
                                     chromatag.BoardTag("tag16h5", 2, 0.05, [0.1, 0, 0])])
    assert [t.family for t in board.tags] == ["16h5", "16h5"]
    assert np.allclose(board.tags[1].position, [0.1, 0, 0])
    with pytest.raises(chromatag.Error, match="twice"):
        chromatag.Board("bad", [chromatag.BoardTag("16h5", 1, 0.05, [0, 0, 0])] * 2)
    bundle = tmp_path / "tags.yaml"
    bundle.write_text("tag_bundles:\n  - name: cube\n    family: 36h11\n    layout:\n"
                      "      - {id: 4, size: 0.06, x: 0, y: 0, z: 0.05, qw: 1, qx: 0, qy: 0, qz: 0}\n")
    cube = chromatag.Board.from_file(str(bundle))
    assert cube.name == "cube" and cube.tags[0].id == 4 and cube.tags[0].family == "36h11"
    with pytest.raises(chromatag.Error, match="has no bundle 'box'"):
        chromatag.Board.from_file(str(bundle) + "#box")


def test_measure_bundle_recovers_the_tags_poses(tmp_path):
    # scripts/measure_bundle.py on `detect --json` lines made from a known
    # bundle (tags on three faces of a box, one twice the size) seen from 12
    # sides with noise: positions within 1 mm, rotations within 0.5 degrees.
    import importlib.util
    spec = importlib.util.spec_from_file_location(
        "measure_bundle", os.path.join(os.path.dirname(__file__), "../../scripts/measure_bundle.py"))
    measure_bundle = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(measure_bundle)
    rng = np.random.default_rng(5)
    truth = {0: (np.eye(3), np.zeros(3)),
             4: (cv2.Rodrigues(np.array([0, np.pi / 2, 0]))[0], np.array([0.08, 0, -0.05])),
             7: (cv2.Rodrigues(np.array([-np.pi / 2, 0, 0]))[0], np.array([0, 0.07, -0.04]))}
    sizes = {0: 0.04, 4: 0.04, 7: 0.08}
    lines = []
    for view in range(12):
        camera_r = cv2.Rodrigues(np.array([np.pi, 0, 0]) + rng.normal(0, 0.35, 3))[0]
        camera_t = np.array([0.02, -0.01, 0.6]) + rng.normal(0, 0.03, 3)
        detections = []
        for tag, (r, t) in truth.items():
            r_c = cv2.Rodrigues(rng.normal(0, 0.002, 3))[0] @ camera_r @ r
            t_c = camera_r @ t + camera_t + rng.normal(0, 0.0005, 3)
            # detect ran with --tag-size 40mm: the 80 mm tag seems half as far.
            t_c = t_c * 0.04 / sizes[tag]
            detections.append({"family": "16h5", "id": tag,
                               "pose": {"rvec": cv2.Rodrigues(r_c)[0].ravel().tolist(),
                                        "tvec": t_c.tolist(), "ambiguity": 0.1}})
        lines.append(json.dumps({"detections": detections}))
    poses = tmp_path / "poses.jsonl"
    poses.write_text("\n".join(lines) + "\n")
    out = tmp_path / "bundle.yaml"
    measure_bundle.main([str(poses), "--tag-size", "0.04", "--master", "0", "--size", "7=0.08",
                         "--name", "box", "-o", str(out)])
    bundle = chromatag.Board.from_file(str(out))
    assert bundle.name == "box" and [t.id for t in bundle.tags] == [0, 4, 7]
    for tag in bundle.tags:
        r, t = truth[tag.id]
        assert tag.size == sizes[tag.id]
        assert np.linalg.norm(tag.position - t) < 0.001
        assert np.degrees(np.linalg.norm(cv2.Rodrigues(tag.rotation.T @ r)[0])) < 0.5


def test_public_names_are_listed_and_documented():
    assert all(hasattr(chromatag, name) for name in chromatag.__all__)
    assert {"Detector", "Detection", "detect", "Error"} <= set(chromatag.__all__)
    assert chromatag.Detection.green_corners.__doc__ and chromatag.Detection.as_dict.__doc__


def test_opencv_holds_the_same_image_budget():
    # Set before the extension (and OpenCV with it) loaded; a user's value kept.
    import subprocess
    import sys
    assert os.environ.get("OPENCV_IO_MAX_IMAGE_PIXELS") == str(1 << 28)
    code = "import os, chromatag; print(os.environ['OPENCV_IO_MAX_IMAGE_PIXELS'])"
    env = dict(os.environ, OPENCV_IO_MAX_IMAGE_PIXELS="1000")
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True)
    assert out.stdout.strip() == "1000", out.stderr


def test_hostile_arrays_and_arguments_are_named_errors():
    zero = np.zeros((1, 1, 3), np.uint8)
    detector = chromatag.Detector()
    # Broadcast views claiming gigabytes: refused before any copy, by size.
    for shape, says in (((50000, 50000, 3), "50000 x 50000 pixels, over the limit of 256 Mpx"),
                        ((2147483653, 1, 3), "1 x 2147483653 pixels"),
                        ((0, 2147483653, 3), "2147483653 x 0 pixels")):
        with pytest.raises(chromatag.Error, match=says):
            detector.detect(np.broadcast_to(zero, shape))
    # A view within the budget is still read (copied once).
    assert detector.detect(np.broadcast_to(zero, (64, 64, 3))) == []
    # Empty images of 3 or 4 channels hold no tag (found by fuzz_python_arrays:
    # an empty BGRA one reached OpenCV's cvtColor).
    for shape in ((0, 0, 3), (5, 0, 3), (5, 0, 4), (0, 5, 4)):
        assert detector.detect(np.zeros(shape, np.uint8)) == []
    cases = [
        (lambda: chromatag.Detector(tag_size="40mm"), "tag_size must be a number .metres., not str '40mm'"),
        (lambda: chromatag.Detector(step=2**70), "option step must be a number that fits in 64 bits"),
        (lambda: chromatag.generate("/nonexistent/x.pdf", ids=[2**40]), "ids must be tag IDs"),
        (lambda: chromatag.generate("/nonexistent/x.pdf", ids=2**40), "ids must be tag IDs"),
        (lambda: detector.detect(zero, estimate_tag_pose=True, camera_params="abc", tag_size=0.1),
         r"camera_params must be \(fx, fy, cx, cy\), not str 'abc'"),
        (lambda: detector.detect(zero, estimate_tag_pose=True, camera_params=(1, 1, 0, 0),
                                 tag_size="big"), "tag_size must be a number"),
        (lambda: chromatag.Board("b", [1, 2]), "a Board's tags must be BoardTag objects, not int 1"),
    ]
    for call, says in cases:
        with pytest.raises(chromatag.Error, match=says):
            call()


def test_paths_are_str_or_pathlike_and_none_is_none(tmp_path):
    # None was read as a file named "None"; a pathlib.Path was a TypeError.
    chromatag.Detector(config=None, camera_file=None)
    sheet = tmp_path / "tags.pdf"
    assert chromatag.generate(sheet, ids=[0, 1]) == [str(sheet), str(sheet) + ".json"]
    assert chromatag.verify(sheet).passed
    with pytest.raises(chromatag.Error, match="no such file"):
        chromatag.read_camera(tmp_path / "camera.yaml")
    with pytest.raises(chromatag.Error, match="camera.yaml"):
        chromatag.Detector(camera_file=tmp_path / "camera.yaml")
    with pytest.raises(TypeError, match="config must be a path \\(str or os.PathLike\\) or None"):
        chromatag.Detector(config=3)
