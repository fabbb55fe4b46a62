"""ChromaTag: coloured fiducial markers (DeGol, Bretl and Hoiem, ICCV 2017).

    import cv2, chromatag
    detector = chromatag.Detector()                 # 16h5 and 36h11
    for tag in detector.detect(cv2.imread("photo.jpg")):
        print(tag.family, tag.id, tag.corners)

See docs/python.md.
"""
from ._chromatag import (  # noqa: F401
    Board,
    BoardPose,
    BoardTag,
    Detection,
    Detector,
    Error,
    Pose,
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
    "Pose",
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
    "render_tag",
    "verify",
    "verify_print",
]


def detect(image, order="bgr", **options):
    """One-off detection with a Detector built from ``options``; build a Detector
    once and reuse it for a stream of frames."""
    return Detector(**options).detect(image, order)
