// vkvo.SuperPoint, vkvo.SuperGlue, vkvo.NNMatcher and vkvo.imread: the networks on their own, on numpy arrays.
// Each object holds its network (weights and per-size buffers on the device) and a lock: one call at a time per
// object, with the GIL released while the device works, so that threads with objects of their own run together.
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <utility>

#include <fmt/format.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>
#include <opencv2/imgcodecs.hpp>

#include "features/nn_matcher.hpp"
#include "features/superglue.hpp"
#include "features/superpoint.hpp"
#include "python/arrays.hpp"
#include "python/bindings.hpp"
#include "python/common.hpp"
#include "tools/convert/model_locator.hpp"

namespace vkvo::python {
namespace {

// A model argument as a loaded pack: a .vkvopack, or an .onnx converted once into the cache (as `vkvo run` does);
// None searches `stem` where `vkvo run` does.
io::ModelPack load_pack(const std::optional<fs::path>& model, const std::string& stem, io::NetworkKind kind) {
  if (model) existing_path(*model, fmt::format("{} model", io::to_string(kind)));
  std::optional<convert::LocatedModel> located;
  {
    const py::gil_scoped_release release;
    located = convert::locate_model(stem, model.value_or(fs::path()), convert::default_model_search(VKVO_SOURCE_DIR));
  }
  if (!located) raise(PyExc_FileNotFoundError, convert::superpoint_help());
  const py::gil_scoped_release release;
  return io::ModelPack::load(located->pack, kind);
}

std::pair<int, int> size_argument(const std::optional<std::pair<int, int>>& size, const char* what) {
  if (!size) raise(PyExc_ValueError, fmt::format("{}: (width, height) of the image is needed", what));
  if (size->first <= 0 || size->second <= 0)
    raise(PyExc_ValueError,
          fmt::format("{}: expected a positive (width, height), got ({}, {})", what, size->first, size->second));
  return *size;
}

py::tuple matches_to_python(const features::PointMatches& matches) {
  const auto n = static_cast<py::ssize_t>(matches.matches0.size());
  return py::make_tuple(int_array({n}, matches.matches0.data()), float_array({n}, matches.scores0.data()));
}

// A network (or matcher) on the device of a `device` argument, with the context it runs on and a lock: calls run
// one at a time, with the GIL released.
template <typename Network>
class OnDevice {
 public:
  // Creates Network(context, args...) with the GIL released.
  template <typename... Args>
  explicit OnDevice(const py::object& device, const Args&... args) {
    const std::string selector = device_argument(device);
    const py::gil_scoped_release release;
    context_ = shared_context(selector);
    network_ = std::make_unique<Network>(*context_, args...);
  }

  // work(network), with the GIL released and the lock held.
  template <typename Work>
  auto run(const Work& work) {
    const py::gil_scoped_release release;
    const std::lock_guard lock(mutex_);
    return work(*network_);
  }

  const Network& network() const { return *network_; }
  std::string device() const { return context_->caps().name; }

 private:
  std::shared_ptr<const rt::Context> context_;  // before the network, which uses it until destroyed
  std::unique_ptr<Network> network_;
  std::mutex mutex_;
};

features::SuperPointParams superpoint_params(const std::string& precision, float keypoint_threshold, int nms_radius,
                                             int remove_borders, int max_keypoints, bool subpixel) {
  features::SuperPointParams params;
  params.keypoint_threshold = keypoint_threshold;
  params.nms_radius = nms_radius;
  params.remove_borders = remove_borders;
  params.max_keypoints = max_keypoints;
  params.subpixel = subpixel;
  params.precision = precision_argument(precision);
  return params;
}

class SuperPointObject {
 public:
  SuperPointObject(const std::optional<fs::path>& model, const py::object& device, const std::string& precision,
                   float keypoint_threshold, int nms_radius, int remove_borders, int max_keypoints, bool subpixel)
      : superpoint_(
            device, load_pack(model, "superpoint_v1", io::NetworkKind::superpoint),
            superpoint_params(precision, keypoint_threshold, nms_radius, remove_borders, max_keypoints, subpixel)) {}

  py::tuple detect(const py::handle& image, bool dense) {
    const ImageArgument input = image_argument(image, "SuperPoint.detect image");
    features::SuperPointDense maps;
    const features::PointFeatures result = superpoint_.run(
        [&](features::SuperPoint& superpoint) { return superpoint.detect(grey(input.mat), dense ? &maps : nullptr); });
    py::tuple outputs = features_to_python(result);
    if (!dense) return outputs;
    const py::ssize_t h = maps.cells_h, w = maps.cells_w, dim = descriptor_dim();
    return py::make_tuple(outputs[0], outputs[1], outputs[2], float_array({h * 8, w * 8}, maps.scores.data()),
                          float_array({dim, h, w}, maps.descriptors.data()));
  }

  std::string precision() const { return std::string(rt::to_string(superpoint_.network().precision())); }
  std::string device() const { return superpoint_.device(); }
  int descriptor_dim() const { return superpoint_.network().descriptor_dim(); }

 private:
  OnDevice<features::SuperPoint> superpoint_;
};

class SuperGlueObject {
 public:
  SuperGlueObject(const fs::path& model, const py::object& device, const std::string& precision, float match_threshold,
                  int sinkhorn_iterations)
      : superglue_(device, load_pack(model, "superglue", io::NetworkKind::superglue),
                   features::SuperGlueParams{.match_threshold = match_threshold,
                                             .sinkhorn_iterations = sinkhorn_iterations,
                                             .precision = precision_argument(precision)}) {}

  py::tuple match(const py::handle& features0, const py::handle& features1,
                  const std::optional<std::pair<int, int>>& image_size,
                  const std::optional<std::pair<int, int>>& image_size1, bool dense) {
    const auto size0 = size_argument(image_size, "SuperGlue.match image_size");
    const auto size1 = image_size1 ? size_argument(image_size1, "SuperGlue.match image_size1") : size0;
    const auto a = features_argument(features0, "SuperGlue.match features0", size0);
    const auto b = features_argument(features1, "SuperGlue.match features1", size1);
    Eigen::MatrixXf log_assignment;
    const features::PointMatches matches = superglue_.run(
        [&](features::SuperGlue& superglue) { return superglue.match(a, b, dense ? &log_assignment : nullptr); });
    py::tuple outputs = matches_to_python(matches);
    if (!dense) return outputs;
    const Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> rows = log_assignment;
    return py::make_tuple(outputs[0], outputs[1], float_array({rows.rows(), rows.cols()}, rows.data()));
  }

  std::string precision() const { return std::string(rt::to_string(superglue_.network().precision())); }
  std::string device() const { return superglue_.device(); }

 private:
  OnDevice<features::SuperGlue> superglue_;
};

class NnMatcherObject {
 public:
  NnMatcherObject(const py::object& device, float max_cosine_distance, float ratio)
      : matcher_(device, features::NnMatcherParams{.max_cosine_distance = max_cosine_distance, .ratio = ratio}) {}

  py::tuple match(const py::handle& features0, const py::handle& features1) {
    // The matcher compares descriptors only; the image size is not used.
    const auto a = features_argument(features0, "NNMatcher.match features0", {0, 0});
    const auto b = features_argument(features1, "NNMatcher.match features1", {0, 0});
    if (a.size() > 0 && b.size() > 0 && a.descriptors.cols() != b.descriptors.cols())
      raise(PyExc_ValueError, fmt::format("NNMatcher.match: descriptors of {} and {} dimensions", a.descriptors.cols(),
                                          b.descriptors.cols()));
    return matches_to_python(matcher_.run([&](features::NnMatcher& matcher) { return matcher.match(a, b); }));
  }

  std::string device() const { return matcher_.device(); }

 private:
  OnDevice<features::NnMatcher> matcher_;
};

py::array_t<std::uint8_t> imread(const fs::path& path, bool color) {
  existing_path(path, "image");
  cv::Mat image;
  {
    const py::gil_scoped_release release;
    image = cv::imread(path.string(), color ? cv::IMREAD_COLOR : cv::IMREAD_GRAYSCALE);
  }
  if (image.empty())
    raise(PyExc_ValueError, fmt::format("cannot decode image {} (corrupt or not an image)", path.string()));
  return image_to_python(image);
}

}  // namespace

void bind_features(py::module_& m) {
  const features::SuperPointParams sp;
  py::class_<SuperPointObject>(m, "SuperPoint", R"(SuperPoint keypoints and descriptors on a Vulkan device.

model: a .vkvopack, or an .onnx (converted once into the cache, as `vkvo run` does); None looks for
    superpoint_v1 where `vkvo run` does ($VKVO_MODELS, models/, $VKVO_DATA/models, ../shared/models).
device: None ($VKVO_DEVICE, else the best device), an index or a name substring (vkvo.devices()).
precision: "auto" (the device's preferred), "fp32", "fp16s" (16-bit storage) or "fp16".
The post-processing parameters default to the reference's (threshold 0.005, NMS radius 4, border 4, top 400;
max_keypoints <= 0 keeps every keypoint). subpixel=True moves each keypoint to the score map's sub-pixel peak;
the default keeps the reference's whole pixels.)")
      .def(
          py::init<const std::optional<fs::path>&, const py::object&, const std::string&, float, int, int, int, bool>(),
          py::arg("model") = py::none(), py::arg("device") = py::none(), py::arg("precision") = "auto",
          py::arg("keypoint_threshold") = sp.keypoint_threshold, py::arg("nms_radius") = sp.nms_radius,
          py::arg("remove_borders") = sp.remove_borders, py::arg("max_keypoints") = sp.max_keypoints,
          py::arg("subpixel") = sp.subpixel)
      .def("detect", &SuperPointObject::detect, py::arg("image"), py::arg("dense") = false,
           R"(Keypoints of one image: numpy uint8, (H, W) grey or (H, W, 3) BGR, any strides, at least 16 x 16.

Returns (keypoints (N, 2) float32 x, y in pixels, scores (N,) float32, descriptors (N, 256) float32),
score-descending; with dense=True also the dense scores (H8, W8), H8 = H // 8 * 8, before NMS, and the
dense descriptors (256, H // 8, W // 8), L2-normalised per cell.)")
      .def_property_readonly("precision", &SuperPointObject::precision)
      .def_property_readonly("device", &SuperPointObject::device)
      .def_property_readonly("descriptor_dim", &SuperPointObject::descriptor_dim);

  const features::SuperGlueParams sg;
  py::class_<SuperGlueObject>(m, "SuperGlue", R"(SuperGlue point matching on a Vulkan device.

model: a .vkvopack or an .onnx SuperGlue (converted once into the cache). device, precision: as for SuperPoint.)")
      .def(py::init<const fs::path&, const py::object&, const std::string&, float, int>(), py::arg("model"),
           py::arg("device") = py::none(), py::arg("precision") = "auto",
           py::arg("match_threshold") = sg.match_threshold, py::arg("sinkhorn_iterations") = sg.sinkhorn_iterations)
      .def("match", &SuperGlueObject::match, py::arg("features0"), py::arg("features1"),
           py::arg("image_size") = py::none(), py::arg("image_size1") = py::none(), py::arg("dense") = false,
           R"(Matches two keypoint sets, each (keypoints (N, 2), scores (N,), descriptors (N, D)) as
SuperPoint.detect returns them. image_size: (width, height) of the images, which normalises the keypoints
(image_size1: the second image's, when it differs).

Returns (matches0 (N,) int32: index into features1 or -1, scores0 (N,) float32); with dense=True also the
log-assignment ((N + 1) x (M + 1) float32, dustbins last).)")
      .def_property_readonly("precision", &SuperGlueObject::precision)
      .def_property_readonly("device", &SuperGlueObject::device);

  const features::NnMatcherParams nn;
  py::class_<NnMatcherObject>(m, "NNMatcher", R"(Mutual-nearest-neighbour matching of descriptors on a Vulkan device.

A pair is kept when 1 - cosine similarity <= max_cosine_distance and, when ratio > 0, it passes Lowe's ratio
test on L2 distances.)")
      .def(py::init<const py::object&, float, float>(), py::arg("device") = py::none(),
           py::arg("max_cosine_distance") = nn.max_cosine_distance, py::arg("ratio") = nn.ratio)
      .def("match", &NnMatcherObject::match, py::arg("features0"), py::arg("features1"),
           R"(Returns (matches0 (N,) int32: index into features1 or -1, scores0 (N,) float32: the cosine
similarity of each match, 0 where unmatched).)")
      .def_property_readonly("device", &NnMatcherObject::device);

  m.def("imread", &imread, py::arg("path"), py::arg("color") = false,
        "An image file as numpy uint8: (H, W) grey, or with color=True (H, W, 3) BGR.");
}

}  // namespace vkvo::python
