// The helpers common.h declares.
#include "common.h"

#include <climits>
#include <string>
#include <vector>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "chromatag/base/input_file.h"

namespace chromatag::python {

PixelOrder OrderFrom(const std::string& order) {
  if (order == "bgr" || order == "BGR") return PixelOrder::kBgr;
  if (order == "rgb" || order == "RGB") return PixelOrder::kRgb;
  throw Error("unknown pixel order '" + order +
              "' (allowed: \"bgr\", as OpenCV reads, or \"rgb\")");
}

cv::Mat ColourImage(const py::object& object, py::object* keep) {
  // None is what cv2.imread gives for a file it could not read.
  if (object.is_none()) throw Error("the image is None (did cv2.imread fail to read the file?)");
  if (!py::isinstance<py::array>(object))
    throw Error("the image must be a numpy array (H x W x 3, uint8), not " +
                std::string(py::str(py::type::of(object).attr("__name__"))));
  const py::array image = py::reinterpret_borrow<py::array>(object);
  if (!py::isinstance<py::array_t<uint8_t>>(image) || image.dtype().kind() != 'u' ||
      image.itemsize() != 1) {
    throw Error("the image must be 8-bit (dtype uint8), not " +
                std::string(py::str(image.dtype())) +
                ": convert it, e.g. with cv2.convertScaleAbs");
  }
  if (image.ndim() == 2 || (image.ndim() == 3 && image.shape(2) == 1)) {
    throw Error(
        "ChromaTag needs a colour image (H x W x 3): its tags are told apart by colour, and this "
        "one is grey");
  }
  if (image.ndim() != 3 || (image.shape(2) != 3 && image.shape(2) != 4)) {
    throw Error("the image must be H x W x 3 (or x 4), not of shape " +
                std::string(py::str(py::tuple(py::cast(
                    std::vector<py::ssize_t>(image.shape(), image.shape() + image.ndim()))))));
  }
  // The budget before any copy (a broadcast view can claim gigabytes), and
  // sizes a cv::Mat can hold.
  const double pixels = static_cast<double>(image.shape(0)) * static_cast<double>(image.shape(1));
  if (pixels > static_cast<double>(kMaxImagePixels) || image.shape(0) > INT_MAX ||
      image.shape(1) > INT_MAX) {
    throw Error("the image is " + std::to_string(image.shape(1)) + " x " +
                std::to_string(image.shape(0)) + " pixels, over the limit of " +
                std::to_string(kMaxImagePixels >> 20) + " Mpx");
  }
  auto contiguous = py::array_t<uint8_t, py::array::c_style | py::array::forcecast>::ensure(image);
  if (!contiguous) throw py::error_already_set();  // numpy's own error, e.g. MemoryError.
  *keep = contiguous;
  const int rows = static_cast<int>(contiguous.shape(0));
  const int cols = static_cast<int>(contiguous.shape(1));
  const int channels = static_cast<int>(contiguous.shape(2));
  cv::Mat mat(rows, cols, CV_8UC(channels), const_cast<uint8_t*>(contiguous.data()));
  if (channels == 3) return mat;
  if (mat.empty()) return cv::Mat(rows, cols, CV_8UC3);  // Nothing to convert (0 rows or columns).
  cv::Mat three;
  cv::cvtColor(mat, three, cv::COLOR_BGRA2BGR);  // Drops the 4th channel whatever the order.
  return three;
}

py::array_t<double, py::array::c_style | py::array::forcecast> SmallNumbers(
    const py::object& value, py::ssize_t max_count, const std::string& expected) {
  const py::array array = py::array::ensure(value);  // No copy of an array.
  if (!array || array.size() > max_count) throw Error(expected);
  auto numbers = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(array);
  if (!numbers) throw Error(expected);
  return numbers;
}

py::array_t<double> Points(const cv::Point2d* points, int n) {
  py::array_t<double> out({n, 2});
  auto view = out.mutable_unchecked<2>();
  for (int i = 0; i < n; ++i) {
    view(i, 0) = points[i].x;
    view(i, 1) = points[i].y;
  }
  return out;
}

py::array_t<double> Vector(const double* values, int n) {
  py::array_t<double> out(n);
  for (int i = 0; i < n; ++i) out.mutable_at(i) = values[i];
  return out;
}

py::array_t<double> Matrix33(const cv::Matx33d& m) {
  py::array_t<double> out({3, 3});
  auto view = out.mutable_unchecked<2>();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) view(r, c) = m(r, c);
  return out;
}

py::array_t<double> RotationMatrix(const cv::Vec3d& rvec) {
  cv::Matx33d r;
  cv::Rodrigues(rvec, r);
  return Matrix33(r);
}

py::array_t<double> SquareMatrix(const double* values, int n) {
  py::array_t<double> out({n, n});
  auto view = out.mutable_unchecked<2>();
  for (int r = 0; r < n; ++r)
    for (int c = 0; c < n; ++c) view(r, c) = values[r * n + c];
  return out;
}

std::string Describe(const py::handle& value) {
  std::string repr = py::str(py::repr(value));
  if (repr.size() > 40) {
    size_t cut = 37;  // On a UTF-8 character boundary.
    while (cut > 0 && (static_cast<unsigned char>(repr[cut]) & 0xc0) == 0x80) --cut;
    repr = repr.substr(0, cut) + "...";
  }
  return std::string(py::str(value.get_type().attr("__name__"))) + " " + repr;
}

std::string PathOrNone(const py::handle& value, const char* name) {
  if (value.is_none()) return "";
  try {
    return value.cast<std::filesystem::path>().string();
  } catch (const py::cast_error&) {
    throw py::type_error(std::string(name) + " must be a path (str or os.PathLike) or None, not " +
                         py::type::of(value).attr("__name__").cast<std::string>());
  }
}

void PickleAtEveryProtocol(py::object cls) {
  auto reduce = [](const py::object& self) {
    return py::make_tuple(py::module_::import("copyreg").attr("__newobj__"),
                          py::make_tuple(py::type::of(self)), self.attr("__getstate__")());
  };
  py::setattr(cls, "__reduce_ex__",
              py::cpp_function([reduce](const py::object& self, int) { return reduce(self); },
                               py::is_method(cls)));
  py::setattr(cls, "__reduce__", py::cpp_function(reduce, py::is_method(cls)));
}

void RefusePickling(py::object cls, const std::string& why) {
  auto refuse = [why](const py::object& self) -> py::object {
    throw py::type_error("cannot pickle '" +
                         py::type::of(self).attr("__qualname__").cast<std::string>() +
                         "' object: " + why);
  };
  py::setattr(cls, "__reduce_ex__",
              py::cpp_function([refuse](const py::object& self, int) { return refuse(self); },
                               py::is_method(cls)));
  py::setattr(cls, "__reduce__", py::cpp_function(refuse, py::is_method(cls)));
}

}  // namespace chromatag::python
