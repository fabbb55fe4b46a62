// The printer model and its Ceres fit (printer_model.h).
#include "chromatag/calib/printer_model.h"

#include <ceres/ceres.h>

#include <algorithm>
#include <cmath>

#include <opencv2/core.hpp>

namespace chromatag {
namespace {

using ToneBlock = std::array<double, kToneSegments>;

template <typename T>
T SrgbToLinearT(const T& v) {
  using std::pow;
  if (v <= T(0.04045)) return v / T(12.92);
  return pow((v + T(0.055)) / T(1.055), T(2.4));
}

template <typename T>
T ToneT(const T* log_increments, double x) {
  using std::exp;
  x = std::clamp(x, 0.0, 1.0);
  const double position = x * kToneSegments;
  const int segment = std::min(kToneSegments - 1, static_cast<int>(position));
  const double fraction = position - segment;
  T total(0.0), below(0.0);
  for (int k = 0; k < kToneSegments; ++k) {
    const T step = exp(log_increments[k]);
    total += step;
    if (k < segment) below += step;
    if (k == segment) below += T(fraction) * step;
  }
  return below / total;
}

template <typename T>
T LabF(const T& t) {
  using std::cbrt;
  constexpr double kDelta = 6.0 / 29.0;
  if (t > T(kDelta * kDelta * kDelta)) return cbrt(t);
  return t / T(3.0 * kDelta * kDelta) + T(4.0 / 29.0);
}

// sent -> Lab relative to the paper white (D65 white of spec section 5).
template <typename T>
void PredictT(const T* tone_r, const T* tone_g, const T* tone_b, const T* matrix, const T* offset,
              const Rgb& sent, T* lab) {
  const T lin[3] = {SrgbToLinearT(ToneT(tone_r, sent.r)), SrgbToLinearT(ToneT(tone_g, sent.g)),
                    SrgbToLinearT(ToneT(tone_b, sent.b))};
  T xyz[3];
  for (int i = 0; i < 3; ++i) {
    xyz[i] = offset[i];
    for (int j = 0; j < 3; ++j) xyz[i] += matrix[3 * i + j] * lin[j];
  }
  const T fx = LabF(xyz[0] / T(kD65White.X));
  const T fy = LabF(xyz[1] / T(kD65White.Y));
  const T fz = LabF(xyz[2] / T(kD65White.Z));
  lab[0] = T(116.0) * fy - T(16.0);
  lab[1] = T(500.0) * (fx - fy);
  lab[2] = T(200.0) * (fy - fz);
}

struct LabResidual {
  Rgb sent;
  Lab measured;
  template <typename T>
  bool operator()(const T* r, const T* g, const T* b, const T* matrix, const T* offset,
                  T* residual) const {
    T lab[3];
    PredictT(r, g, b, matrix, offset, sent, lab);
    residual[0] = lab[0] - T(measured.L);
    residual[1] = lab[1] - T(measured.a);
    residual[2] = lab[2] - T(measured.b);
    return true;
  }
};

struct Smoothness {
  double weight;
  template <typename T>
  bool operator()(const T* curve, T* residual) const {
    for (int k = 1; k + 1 < kToneSegments; ++k)
      residual[k - 1] = T(weight) * (curve[k + 1] - T(2.0) * curve[k] + curve[k - 1]);
    return true;
  }
};

double Distance2(const std::vector<PrinterModel>& models, const Lab& target, const Rgb& rgb) {
  double sum = 0;
  for (const PrinterModel& m : models) {
    const Lab p = m.Predict(rgb);
    sum += (p.L - target.L) * (p.L - target.L) + (p.a - target.a) * (p.a - target.a) +
           (p.b - target.b) * (p.b - target.b);
  }
  return sum;
}

}  // namespace

bool PrinterModelOptions::IsValid(std::string* error) const {
  if (!(huber_delta > 0) || !(smoothness >= 0) || max_iterations < 1) {
    if (error) *error = "printer model: huber_delta > 0, smoothness >= 0, max_iterations >= 1";
    return false;
  }
  return true;
}

PrinterModel::PrinterModel() {
  for (int j = 0; j < 3; ++j) {
    Rgb unit;
    (j == 0 ? unit.r : j == 1 ? unit.g : unit.b) = 1.0;
    const Xyz column = LinearRgbToXyz(unit);
    matrix[j] = column.X;
    matrix[3 + j] = column.Y;
    matrix[6 + j] = column.Z;
  }
}

Lab PrinterModel::Predict(const Rgb& sent) const {
  double lab[3];
  PredictT(tone[0].data(), tone[1].data(), tone[2].data(), matrix.data(), offset.data(), sent, lab);
  return {lab[0], lab[1], lab[2]};
}

double PrinterModel::Tone(int channel, double x) const { return ToneT(tone[channel].data(), x); }

namespace {

Rgb AsRgb(const double* v) { return Rgb{v[0], v[1], v[2]}; }

// One model's residual at x and its numeric Jacobian J, added into J^T J
// and J^T r.
void AddNormalEquations(const PrinterModel& m, const Lab& target, const double x[3],
                        double jtj[3][3], double jtr[3]) {
  const auto at = AsRgb;
  const Lab p = m.Predict(at(x));
  const double r[3] = {p.L - target.L, p.a - target.a, p.b - target.b};
  double jac[3][3];
  for (int j = 0; j < 3; ++j) {
    const double h = 1e-5;
    double xp[3] = {x[0], x[1], x[2]}, xm[3] = {x[0], x[1], x[2]};
    xp[j] += h;
    xm[j] -= h;
    const Lab lp = m.Predict(at(xp)), lm = m.Predict(at(xm));
    jac[0][j] = (lp.L - lm.L) / (2 * h);
    jac[1][j] = (lp.a - lm.a) / (2 * h);
    jac[2][j] = (lp.b - lm.b) / (2 * h);
  }
  for (int a = 0; a < 3; ++a) {
    for (int b = 0; b < 3; ++b) {
      for (int i = 0; i < 3; ++i) jtj[a][b] += jac[i][a] * jac[i][b];
    }
    for (int i = 0; i < 3; ++i) jtr[a] += jac[i][a] * r[i];
  }
}

}  // namespace

Rgb InvertPrinter(const std::vector<PrinterModel>& models, const Lab& target, const Rgb& start) {
  // Levenberg-Marquardt on three unknowns with a numeric Jacobian, projected
  // onto the unit cube: a LUT needs thousands of these, each tiny.
  double x[3] = {std::clamp(start.r, 0.0, 1.0), std::clamp(start.g, 0.0, 1.0),
                 std::clamp(start.b, 0.0, 1.0)};
  const auto at = AsRgb;
  double cost = Distance2(models, target, at(x));
  double lambda = 1e-3;
  for (int iteration = 0; iteration < 60 && cost > 1e-10; ++iteration) {
    // Stack residuals over the models: J is (3 * models) x 3.
    double jtj[3][3] = {}, jtr[3] = {};
    for (const PrinterModel& m : models) AddNormalEquations(m, target, x, jtj, jtr);
    bool improved = false;
    for (int attempt = 0; attempt < 8 && !improved; ++attempt) {
      cv::Matx33d a;
      cv::Vec3d rhs;
      for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j)
          a(i, j) = jtj[i][j] + (i == j ? lambda * (jtj[i][i] + 1e-9) : 0);
        rhs[i] = -jtr[i];
      }
      cv::Vec3d step;
      cv::solve(a, rhs, step, cv::DECOMP_SVD);
      double trial[3];
      for (int i = 0; i < 3; ++i) trial[i] = std::clamp(x[i] + step[i], 0.0, 1.0);
      const double trial_cost = Distance2(models, target, at(trial));
      if (trial_cost < cost) {
        improved = true;
        const double gain = cost - trial_cost;
        std::copy(trial, trial + 3, x);
        cost = trial_cost;
        lambda = std::max(1e-7, lambda / 3);
        if (gain < 1e-9 * (1 + cost)) iteration = 1 << 20;  // Converged.
      } else {
        lambda *= 4;
      }
    }
    if (!improved) break;
  }
  return at(x);
}

std::optional<PrinterFit> FitPrinterModel(const std::vector<PrinterSample>& samples,
                                          const PrinterModelOptions& options, std::string* error) {
  if (!options.IsValid(error)) return std::nullopt;
  if (samples.size() < 20) {
    if (error)
      *error = "too few usable patches to fit the printer (" + std::to_string(samples.size()) +
               ", need 20)";
    return std::nullopt;
  }
  PrinterFit fit;
  PrinterModel& m = fit.model;
  ceres::Problem problem;
  for (const PrinterSample& s : samples) {
    auto* cost =
        new ceres::AutoDiffCostFunction<LabResidual, 3, kToneSegments, kToneSegments, kToneSegments,
                                        9, 3>(new LabResidual{s.sent, s.measured});
    problem.AddResidualBlock(cost, new ceres::HuberLoss(options.huber_delta), m.tone[0].data(),
                             m.tone[1].data(), m.tone[2].data(), m.matrix.data(), m.offset.data());
  }
  if (options.smoothness > 0) {
    for (int c = 0; c < 3; ++c) {
      problem.AddResidualBlock(
          new ceres::AutoDiffCostFunction<Smoothness, kToneSegments - 2, kToneSegments>(
              new Smoothness{options.smoothness}),
          nullptr, m.tone[c].data());
    }
  }
  ceres::Solver::Options solver;
  solver.linear_solver_type = ceres::DENSE_QR;
  solver.max_num_iterations = options.max_iterations;
  solver.num_threads = 1;
  solver.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(solver, &problem, &summary);
  fit.iterations = static_cast<int>(summary.iterations.size());
  fit.converged = summary.termination_type == ceres::CONVERGENCE;
  for (const PrinterSample& s : samples) {
    const double de = Ciede2000(m.Predict(s.sent), s.measured);
    fit.residual_de.push_back(de);
    fit.mean_de += de / samples.size();
    fit.max_de = std::max(fit.max_de, de);
  }
  return fit;
}

}  // namespace chromatag
