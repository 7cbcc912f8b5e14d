#include "python/arrays.hpp"

#include <algorithm>
#include <cstring>
#include <string>

#include <fmt/format.h>
#include <opencv2/imgproc.hpp>

#include "python/common.hpp"

namespace vkvo::python {
namespace {

std::string shape_text(const py::array& array) {
  std::string text = "(";
  for (py::ssize_t i = 0; i < array.ndim(); ++i) text += fmt::format("{}{}", i ? ", " : "", array.shape(i));
  return text + (array.ndim() == 1 ? ",)" : ")");
}

std::string dtype_text(const py::array& array) { return py::str(array.dtype()).cast<std::string>(); }

py::array require_array(const py::handle& value, const char* what) {
  if (!py::isinstance<py::array>(value))
    raise(PyExc_TypeError, fmt::format("{}: expected a numpy array, got {}", what,
                                       py::str(py::type::of(value).attr("__name__")).cast<std::string>()));
  return py::reinterpret_borrow<py::array>(value);
}

using FloatArray = py::array_t<float, py::array::c_style | py::array::forcecast>;

// `value` as a C-ordered float32 array (a copy where it is another dtype or order); ValueError for non-numbers.
FloatArray float_argument(const py::handle& value, const char* what) {
  const py::array array = require_array(value, what);
  const char kind = array.dtype().kind();
  if (kind != 'f' && kind != 'i' && kind != 'u')
    raise(PyExc_ValueError, fmt::format("{}: expected real numbers, got dtype {}", what, dtype_text(array)));
  auto converted = FloatArray::ensure(array);
  if (!converted) throw py::error_already_set();
  return converted;
}

}  // namespace

ImageArgument image_argument(const py::handle& image, const char* what) {
  const py::array array = require_array(image, what);
  if (array.dtype().kind() != 'u' || array.dtype().itemsize() != 1) {
    const char kind = array.dtype().kind();
    raise(PyExc_ValueError,
          fmt::format("{}: expected a uint8 image, got dtype {}{}", what, dtype_text(array),
                      kind == 'f' ? " (a float image in [0, 1] converts with (image * 255).round().astype(numpy.uint8))"
                                  : " (convert it with .astype(numpy.uint8) where its values are 0-255)"));
  }
  const bool grey = array.ndim() == 2 || (array.ndim() == 3 && array.shape(2) == 1);
  const bool bgr = array.ndim() == 3 && array.shape(2) == 3;
  if (!grey && !bgr)
    raise(PyExc_ValueError,
          fmt::format("{}: expected shape (H, W) or (H, W, 3) (BGR), got {}", what, shape_text(array)));
  if (array.shape(0) == 0 || array.shape(1) == 0)
    raise(PyExc_ValueError, fmt::format("{}: the image is empty, shape {}", what, shape_text(array)));
  ImageArgument result{py::array_t<std::uint8_t, py::array::c_style>::ensure(array), {}};
  if (!result.pixels) throw py::error_already_set();
  // cv::Mat wants a non-const pointer; the image is only read.
  result.mat = cv::Mat(static_cast<int>(array.shape(0)), static_cast<int>(array.shape(1)), grey ? CV_8UC1 : CV_8UC3,
                       const_cast<void*>(result.pixels.data()));
  return result;
}

cv::Mat grey(const cv::Mat& image) {
  if (image.type() == CV_8UC1) return image;
  cv::Mat converted;
  cv::cvtColor(image, converted, cv::COLOR_BGR2GRAY);
  return converted;
}

features::PointFeatures features_argument(const py::handle& features, const char* what,
                                          std::pair<int, int> image_size) {
  if (py::isinstance<py::array>(features) || !py::isinstance<py::sequence>(features) || py::len(features) < 3)
    raise(PyExc_TypeError,
          fmt::format("{}: expected (keypoints, scores, descriptors) as SuperPoint.detect returns", what));
  const py::sequence parts = py::reinterpret_borrow<py::sequence>(features);
  const auto keypoints = float_argument(parts[0], fmt::format("{} keypoints", what).c_str());
  const auto scores = float_argument(parts[1], fmt::format("{} scores", what).c_str());
  const auto descriptors = float_argument(parts[2], fmt::format("{} descriptors", what).c_str());
  if (keypoints.ndim() != 2 || keypoints.shape(1) != 2)
    raise(PyExc_ValueError, fmt::format("{} keypoints: expected shape (N, 2), got {}", what, shape_text(keypoints)));
  const py::ssize_t n = keypoints.shape(0);
  if (scores.ndim() != 1 || scores.shape(0) != n)
    raise(PyExc_ValueError,
          fmt::format("{} scores: expected shape ({},) for the {} keypoints, got {}", what, n, n, shape_text(scores)));
  if (descriptors.ndim() != 2 || descriptors.shape(0) != n || descriptors.shape(1) == 0)
    raise(PyExc_ValueError, fmt::format("{} descriptors: expected shape ({}, D) for the {} keypoints, got {}", what, n,
                                        n, shape_text(descriptors)));
  features::PointFeatures f;
  f.image_width = image_size.first;
  f.image_height = image_size.second;
  const float* xy = keypoints.data();
  for (py::ssize_t i = 0; i < n; ++i) f.keypoints.emplace_back(xy[2 * i], xy[2 * i + 1]);
  f.scores.assign(scores.data(), scores.data() + n);
  f.descriptors.resize(n, descriptors.shape(1));
  std::copy_n(descriptors.data(), descriptors.size(), f.descriptors.data());
  return f;
}

py::tuple features_to_python(const features::PointFeatures& f) {
  const auto n = static_cast<py::ssize_t>(f.size());
  std::vector<float> xy;
  xy.reserve(2 * f.size());
  for (const auto& k : f.keypoints) xy.insert(xy.end(), {k.x(), k.y()});
  return py::make_tuple(float_array({n, 2}, xy.data()), float_array({n}, f.scores.data()),
                        float_array({n, static_cast<py::ssize_t>(f.descriptors.cols())}, f.descriptors.data()));
}

py::array_t<float> float_array(const std::vector<py::ssize_t>& shape, const float* data) {
  py::array_t<float> array(shape);
  if (array.size() > 0) std::memcpy(array.mutable_data(), data, sizeof(float) * array.size());
  return array;
}

py::array_t<int> int_array(const std::vector<py::ssize_t>& shape, const int* data) {
  py::array_t<int> array(shape);
  if (array.size() > 0) std::memcpy(array.mutable_data(), data, sizeof(int) * array.size());
  return array;
}

py::array_t<std::uint8_t> image_to_python(const cv::Mat& image) {
  std::vector<py::ssize_t> shape{image.rows, image.cols};
  if (image.channels() > 1) shape.push_back(image.channels());
  py::array_t<std::uint8_t> array(shape);
  const std::size_t row_bytes = std::size_t(image.cols) * image.elemSize();
  for (int y = 0; y < image.rows; ++y) std::memcpy(array.mutable_data() + y * row_bytes, image.ptr(y), row_bytes);
  return array;
}

py::object json_to_python(const nlohmann::json& value) {
  switch (value.type()) {
    case nlohmann::json::value_t::object: {
      py::dict dict;
      for (const auto& [key, item] : value.items()) dict[py::str(key)] = json_to_python(item);
      return dict;
    }
    case nlohmann::json::value_t::array: {
      py::list list;
      for (const auto& item : value) list.append(json_to_python(item));
      return list;
    }
    case nlohmann::json::value_t::string: return py::str(value.get<std::string>());
    case nlohmann::json::value_t::boolean: return py::bool_(value.get<bool>());
    case nlohmann::json::value_t::number_integer: return py::int_(value.get<std::int64_t>());
    case nlohmann::json::value_t::number_unsigned: return py::int_(value.get<std::uint64_t>());
    case nlohmann::json::value_t::number_float: return py::float_(value.get<double>());
    default: return py::none();
  }
}

}  // namespace vkvo::python
