// vkvo_fuzz_seeds DIR: writes a small seed corpus for every fuzz target under DIR/<target>/, each seed a valid
// (or nearly valid) input of a few hundred bytes, so that the fuzzers start inside the formats.
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include <onnx/onnx_pb.h>
#include <opencv2/imgcodecs.hpp>

#include "io/model_pack.hpp"
#include "io/npy.hpp"

namespace fs = std::filesystem;

namespace {

void write(const fs::path& file, const std::string& content) {
  fs::create_directories(file.parent_path());
  std::ofstream(file, std::ios::binary | std::ios::trunc) << content;
}

std::string read(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

void npy_seeds(const fs::path& dir) {
  fs::create_directories(dir);
  const std::vector<float> values = {1.0f, -2.5f, 3.25f, 0.0f, 5.0f, 6.0f};
  vkvo::io::write_npy(dir / "f4_2x3.npy", {2, 3}, values.data());
  const std::vector<std::int32_t> ints = {7, -1, 3};
  vkvo::io::write_npy(dir / "i4_3.npy", {3}, ints.data());
  vkvo::io::write_npy(dir / "empty.npy", {0, 2}, values.data());
}

void model_pack_seeds(const fs::path& dir) {
  fs::create_directories(dir);
  vkvo::io::ModelPackWriter w(vkvo::io::NetworkKind::superpoint);
  w.set_number("descriptor_dim", 4);
  w.set_string("source", "fuzz seed");
  w.set_numbers("widths", {2, 4});
  const std::vector<float> bias = {0.5f, -0.5f, 1.0f, 2.0f}, identity = {1.0f, 0.0f, 0.0f, 1.0f};
  w.add_tensor("conv.bias", {4}, "o4", bias);
  w.add_tensor("linear.weight", {2, 2}, "oi", identity);
  w.write(dir / "superpoint.vkvopack");
}

void onnx_seeds(const fs::path& dir) {
  onnx::ModelProto model;
  model.set_ir_version(7);
  model.add_opset_import()->set_version(12);
  onnx::GraphProto* graph = model.mutable_graph();
  graph->set_name("superpoint");
  graph->add_input()->set_name("image");
  graph->add_output()->set_name("scores");
  onnx::TensorProto* weight = graph->add_initializer();
  weight->set_name("conv1a.weight");
  weight->set_data_type(onnx::TensorProto::FLOAT);
  for (int d : {2, 1, 3, 3}) weight->add_dims(d);
  for (int i = 0; i < 18; ++i) weight->add_float_data(0.1f * static_cast<float>(i));
  onnx::TensorProto* bias = graph->add_initializer();
  bias->set_name("conv1a.bias");
  bias->set_data_type(onnx::TensorProto::FLOAT);
  bias->add_dims(2);
  bias->add_float_data(0.0f);
  bias->add_float_data(1.0f);
  onnx::NodeProto* conv = graph->add_node();
  conv->set_op_type("Conv");
  conv->set_name("conv1a");
  conv->add_input("image");
  conv->add_input("conv1a.weight");
  conv->add_input("conv1a.bias");
  conv->add_output("scores");
  onnx::AttributeProto* pads = conv->add_attribute();
  pads->set_name("pads");
  pads->set_type(onnx::AttributeProto::INTS);
  for (int p : {1, 1, 1, 1}) pads->add_ints(p);
  std::string bytes;
  model.SerializeToString(&bytes);
  write(dir / "conv.onnx", bytes);
}

void image_seeds(const fs::path& dir) {
  fs::create_directories(dir);
  cv::Mat gray(20, 24, CV_8UC1);
  for (int r = 0; r < gray.rows; ++r)
    for (int c = 0; c < gray.cols; ++c) gray.at<unsigned char>(r, c) = static_cast<unsigned char>(r * 11 + c * 7);
  cv::imwrite((dir / "gray.png").string(), gray);
  cv::imwrite((dir / "gray.pgm").string(), gray);
  cv::Mat colour16(18, 18, CV_16UC3, cv::Scalar(1000, 20000, 60000));
  cv::imwrite((dir / "colour16.png").string(), colour16);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::cerr << "usage: vkvo_fuzz_seeds TEXT_SEEDS_DIR OUT_DIR\n";
    return 1;
  }
  const fs::path text_seeds = argv[1], out = argv[2];
  // The text formats' seeds live in the tree (fuzz/seeds/<target>/); the binary ones are generated here.
  for (const auto& entry : fs::recursive_directory_iterator(text_seeds))
    if (entry.is_regular_file()) write(out / fs::relative(entry.path(), text_seeds), read(entry.path()));
  npy_seeds(out / "npy");
  model_pack_seeds(out / "model_pack");
  onnx_seeds(out / "onnx");
  image_seeds(out / "image");
  return 0;
}
