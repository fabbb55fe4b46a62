#include "chromatag/detector/detection_json.h"

#include <nlohmann/json.hpp>

namespace chromatag {
namespace {

// nlohmann::json (not ordered_json): keys in alphabetical order, as the
// CLI has always written them.
using Json = nlohmann::json;

std::string Dump(const Json& json) {
  // A name that is not UTF-8 is written with U+FFFD, not refused.
  return json.dump(-1, ' ', false, Json::error_handler_t::replace);
}

Json Points(const std::array<cv::Point2d, 4>& points) {
  Json out = Json::array();
  for (const auto& p : points) out.push_back({p.x, p.y});
  return out;
}

Json Vec3(const cv::Vec3d& v) { return {v[0], v[1], v[2]}; }

// A 6 x 6 covariance as ROS writes one: 36 numbers, row-major.
Json Covariance(const cv::Matx66d& m) { return Json(std::vector<double>(m.val, m.val + 36)); }

Json DetectionObject(const Detection& d) {
  Json item = {{"family", d.family->name()},
               {"id", d.id},
               {"hamming", d.hamming},
               {"margin", d.decision_margin},
               {"corners", Points(d.corners)},
               {"green_corners", Points(d.green_corners)},
               {"red_corners", Points(d.red_corners)}};
  if (d.has_pose) {
    item["pose"] = {{"rvec", Vec3(d.pose.rvec)},
                    {"tvec", Vec3(d.pose.tvec)},
                    {"rms_error_px", d.pose.rms_error_px},
                    {"ambiguity", d.pose.ambiguity},
                    {"covariance", Covariance(d.pose.covariance)}};
  }
  return item;
}

Json Rejected(const std::vector<RejectedCandidate>& rejected) {
  Json out = Json::array();
  for (const RejectedCandidate& r : rejected) {
    Json outline = Json::array();
    for (const auto& p : r.outline) outline.push_back({p.x, p.y});
    Json record = {{"stage", StageName(r.stage)},
                   {"reason", RejectReasonName(r.reason)},
                   {"seed", {r.seed.x, r.seed.y}},
                   {"centre", {r.centre.x, r.centre.y}},
                   {"outline", outline}};
    // The second path's own reason, when it tried the candidate too.
    if (r.grown) record["grow_reason"] = RejectReasonName(r.grow_reason);
    out.push_back(std::move(record));
  }
  return out;
}

Json BoardObject(const Board& board, const BoardPose& pose,
                 const std::vector<Detection>& detections) {
  Json used = Json::array(), rejected = Json::array();
  for (int i : pose.tags_used) used.push_back(board.tags[i].id);
  for (int i : pose.detections_rejected) rejected.push_back(detections[i].id);
  return {{"name", board.name},          {"rvec", Vec3(pose.rvec)},
          {"tvec", Vec3(pose.tvec)},     {"tags_used", used},
          {"tags_rejected", rejected},   {"rms_error_px", pose.rms_error_px},
          {"ambiguity", pose.ambiguity}, {"covariance", Covariance(pose.covariance)}};
}

}  // namespace

std::string DetectionJson(const Detection& detection) { return Dump(DetectionObject(detection)); }

std::string FrameJson(const FrameJsonRecord& frame, const std::vector<Detection>& detections) {
  Json items = Json::array();
  for (const Detection& d : detections) items.push_back(DetectionObject(d));
  Json line = {{"file", frame.file},     {"frame", frame.frame},     {"width", frame.width},
               {"height", frame.height}, {"time_us", frame.time_us}, {"detections", items}};
  if (frame.board) {
    line["board"] =
        frame.board_pose ? BoardObject(*frame.board, *frame.board_pose, detections) : Json(nullptr);
  }
  if (frame.timestamp) line["timestamp"] = *frame.timestamp;
  if (!frame.overlay.empty()) line["overlay"] = frame.overlay;
  if (frame.rejected) line["rejected"] = Rejected(*frame.rejected);
  return Dump(line);
}

}  // namespace chromatag
