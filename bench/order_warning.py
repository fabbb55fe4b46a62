"""How well the Python module's channel-order warning works (docs/python.md,
"Channel order"): rendered frames with one tag passed in the wrong order
(warned?) and tag-free frames and OpenCV's sample photos in both orders
(warned wrongly?).

    PYTHONPATH=build/python /usr/bin/python3 bench/order_warning.py
"""
import glob
import random
import warnings

import cv2
import numpy as np

import chromatag

rng = np.random.default_rng(5)


def warns(detector, image, order="bgr"):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        found = detector.detect(image, order=order)
    return found, bool(caught)


def frame(family, tag_id, side_px, tilt_deg, noise, blur, jpeg):
    """One tag, side_px wide, turned tilt_deg about the vertical axis, on a flat random colour."""
    tag = chromatag.render_tag(family, tag_id, 12)
    h, w = tag.shape[:2]
    image = np.full((480, 640, 3), rng.integers(60, 200, 3), np.uint8)
    s, c = side_px / w, np.cos(np.radians(tilt_deg))
    cx, cy = rng.uniform(150, 490), rng.uniform(130, 350)
    dst = np.float32([[cx - s * w / 2 * c, cy - s * h / 2], [cx + s * w / 2 * c, cy - s * h / 2 * 0.9],
                      [cx + s * w / 2 * c, cy + s * h / 2 * 0.9], [cx - s * w / 2 * c, cy + s * h / 2]])
    H = cv2.getPerspectiveTransform(np.float32([[0, 0], [w, 0], [w, h], [0, h]]), dst)
    mask = cv2.warpPerspective(np.ones((h, w), np.uint8), H, (640, 480), flags=cv2.INTER_NEAREST)
    warped = cv2.warpPerspective(tag, H, (640, 480), flags=cv2.INTER_AREA)
    image[mask > 0] = warped[mask > 0]
    if blur:
        image = cv2.GaussianBlur(image, (0, 0), blur)
    image = np.clip(image + rng.normal(0, noise, image.shape), 0, 255).astype(np.uint8)
    if jpeg:
        image = cv2.imdecode(cv2.imencode(".jpg", image, [cv2.IMWRITE_JPEG_QUALITY, int(jpeg)])[1], 1)
    return image


def main():
    seen = swapped_empty = swapped_warned = 0
    for i in range(300):
        family = random.Random(i).choice(["16h5", "36h11"])
        ids = chromatag.family(family)["kept_ids"]
        image = frame(family, ids[i % len(ids)], rng.uniform(30, 200), rng.uniform(0, 60),
                      rng.uniform(0, 6), rng.uniform(0, 1.2), rng.choice([0, 90, 75]))
        if not chromatag.Detector().detect(image):
            continue  # Only frames whose tag is found in the right order count.
        seen += 1
        found, warned = warns(chromatag.Detector(), np.ascontiguousarray(image[:, :, ::-1]))
        swapped_empty += not found
        swapped_warned += warned
    print(f"{seen} rendered frames with a tag found: passed in the wrong order, {swapped_empty} "
          f"found nothing and {swapped_warned} warned")

    false = 0
    for _ in range(300):
        image = cv2.resize(rng.integers(0, 256, (12, 16, 3)).astype(np.uint8), (640, 480),
                           interpolation=cv2.INTER_CUBIC)
        image = np.clip(image + rng.normal(0, 4, image.shape), 0, 255).astype(np.uint8)
        false += warns(chromatag.Detector(), image)[1]
    print(f"300 tag-free frames: {false} warned")

    photos = warned = 0
    for path in sorted(glob.glob("/usr/share/doc/opencv-doc/examples/data/*.jpg") +
                       glob.glob("/usr/share/doc/opencv-doc/examples/data/*.png")):
        image = cv2.imread(path, cv2.IMREAD_COLOR)
        if image is None or min(image.shape[:2]) < 64:
            continue
        photos += 1
        for order in ("bgr", "rgb"):
            warned += warns(chromatag.Detector(), image, order)[1]
    print(f"{photos} OpenCV sample photos, both orders: {warned} warned")


if __name__ == "__main__":
    main()
