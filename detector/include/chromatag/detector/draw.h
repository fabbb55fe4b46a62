// Drawing detections for people (the CLI's --overlay), kept apart from
// detection: the detector itself never draws.
#ifndef CHROMATAG_DETECTOR_DRAW_H_
#define CHROMATAG_DETECTOR_DRAW_H_

#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "chromatag/detector/board.h"
#include "chromatag/detector/detection.h"
#include "chromatag/detector/options.h"

namespace chromatag {

// Draws into `canvas` (8-bit BGR): each tag's outer quad, its family and ID,
// a dot on corner 0, and when the detection has a pose and `camera` is given,
// the tag frame's axes (x red, y green, z blue, half a tag long).
void DrawDetections(const std::vector<Detection>& detections, const CameraIntrinsics* camera,
                    double tag_size, cv::Mat* canvas);

// Draws a board's frame at its pose into `canvas` (8-bit BGR): x red, y
// green, z blue, `axis_length` metres long, with the board's name; nothing
// when the axes reach behind the camera.
void DrawBoardPose(const BoardPose& pose, const std::string& name, const CameraIntrinsics& camera,
                   double axis_length, cv::Mat* canvas);

// Draws rejected candidates into `canvas` (8-bit BGR), coloured by the stage
// that rejected them (InitialScan orange, BuildPolygon yellow, PolyToQuad
// magenta, Decode red): the outline known at rejection, the seed as a dot, and
// the reason beside it. Seeds dropped inside an already rejected region are
// grey dots only.
void DrawRejected(const std::vector<RejectedCandidate>& rejected, cv::Mat* canvas);

}  // namespace chromatag

#endif  // CHROMATAG_DETECTOR_DRAW_H_
