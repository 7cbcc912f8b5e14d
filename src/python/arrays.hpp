#pragma once
// numpy arrays in and out. Inputs of any stride and order are copied to C order where they are not already;
// outputs are new arrays that own their data.
#include <cstddef>
#include <utility>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <nlohmann/json.hpp>
#include <opencv2/core/mat.hpp>

#include "features/point_features.hpp"

namespace vkvo::python {

namespace py = pybind11;

// An image argument: numpy uint8, (H, W) grey or (H, W, 3) BGR ((H, W, 1) counts as grey). `mat` views the
// pixels of `pixels`, which keeps them alive: hold it while `mat` is used. ValueError naming `what` for any other
// dtype or shape (a float image gets the conversion it needs spelled out), TypeError for a non-array.
struct ImageArgument {
  py::array pixels;
  cv::Mat mat;
};
ImageArgument image_argument(const py::handle& image, const char* what);

// The image as 8-bit grey (BGR converted as StereoOdometry converts it).
cv::Mat grey(const cv::Mat& image);

// A features argument: a (keypoints (N, 2), scores (N,), descriptors (N, D)) sequence as SuperPoint.detect
// returns it (longer sequences: the rest is ignored), of any real dtype (converted to float32). `image_size`
// (width, height) goes with it. ValueError naming `what` for shapes that disagree.
features::PointFeatures features_argument(const py::handle& features, const char* what, std::pair<int, int> image_size);

// (keypoints (N, 2) float32, scores (N,) float32, descriptors (N, D) float32).
py::tuple features_to_python(const features::PointFeatures& features);

// A new float32 / int32 / uint8 array of `shape` holding a copy of `data` (C order).
py::array_t<float> float_array(const std::vector<py::ssize_t>& shape, const float* data);
py::array_t<int> int_array(const std::vector<py::ssize_t>& shape, const int* data);
// A copy of an 8-bit image: (H, W) or (H, W, channels).
py::array_t<std::uint8_t> image_to_python(const cv::Mat& image);

// JSON as Python objects: dicts, lists, str, int, float, bool, None.
py::object json_to_python(const nlohmann::json& value);

}  // namespace vkvo::python
