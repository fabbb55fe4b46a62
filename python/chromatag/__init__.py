"""ChromaTag: coloured fiducial markers (DeGol, Bretl and Hoiem, ICCV 2017).

    import cv2, chromatag
    detector = chromatag.Detector()                 # 16h5 and 36h11
    for tag in detector.detect(cv2.imread("photo.jpg")):
        print(tag.family, tag.id, tag.corners)

See docs/python.md.
"""
import os as _os

# OpenCV's own image budget, a second line behind the module's own checks:
# OpenCV reads it once, when its library loads with the extension below (so
# it has no effect if cv2 was imported first). A value already set is kept.
_os.environ.setdefault("OPENCV_IO_MAX_IMAGE_PIXELS", str(1 << 28))

from ._chromatag import (  # noqa: E402,F401
    Board,
    BoardPose,
    BoardTag,
    Detection,
    Detector,
    Error,
    FilteredPose,
    Pose,
    PoseFilter,
    SheetVerdict,
    TagVerdict,
    __version__,
    draw_board_pose,
    draw_detections,
    families,
    family,
    generate,
    palette,
    palettes,
    read_camera,
    render_tag,
    verify,
    verify_print,
)


__all__ = [
    "Board",
    "BoardPose",
    "BoardTag",
    "Detection",
    "Detector",
    "Error",
    "FilteredPose",
    "Pose",
    "PoseFilter",
    "SheetVerdict",
    "TagVerdict",
    "__version__",
    "detect",
    "draw_board_pose",
    "draw_detections",
    "families",
    "family",
    "generate",
    "palette",
    "palettes",
    "read_camera",
    "render_tag",
    "verify",
    "verify_print",
]


def detect(image, order="bgr", **options):
    """One-off detection with a Detector built from ``options``; build a Detector
    once and reuse it for a stream of frames."""
    return Detector(**options).detect(image, order)
