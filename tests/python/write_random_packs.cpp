// Writes the random-weight model packs that the data-free Python tests (label `python`) load:
//   vkvo_test_python_packs DIR  ->  DIR/random_superpoint.vkvopack (superpoint_reference.hpp's, seed 1) and
//                                   DIR/random_superglue.vkvopack (superglue_reference.hpp's default: 32-d)
#include <cstdio>
#include <exception>
#include <filesystem>
#include <string>
#include <type_traits>
#include <variant>
#include <vector>

#include "io/model_pack.hpp"
#include "superglue/superglue_reference.hpp"
#include "superpoint/superpoint_reference.hpp"

namespace {

using namespace vkvo;

// The pack as a file: every tensor as stored (fp16 copies included, exact) and every hyper-parameter.
void write_pack(const io::ModelPack& pack, const std::filesystem::path& file) {
  io::ModelPackWriter writer(pack.kind());
  for (const auto& [key, value] : pack.hyper_parameters()) {
    std::visit(
        [&, &key = key](const auto& v) {
          using T = std::decay_t<decltype(v)>;
          if constexpr (std::is_same_v<T, double>)
            writer.set_number(key, v);
          else if constexpr (std::is_same_v<T, std::string>)
            writer.set_string(key, v);
          else
            writer.set_numbers(key, v);
        },
        value);
  }
  for (const auto& tensor : pack.tensors())
    writer.add_tensor(tensor.name, tensor.shape, tensor.layout, pack.floats(tensor.name, tensor.dtype), {tensor.dtype});
  writer.write(file);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s DIR\n", argv[0]);
    return 2;
  }
  try {
    const std::filesystem::path dir = argv[1];
    std::filesystem::create_directories(dir);
    write_pack(features::reference::random_superpoint_pack(1), dir / "random_superpoint.vkvopack");
    write_pack(test::random_superglue_pack({}), dir / "random_superglue.vkvopack");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 1;
  }
  return 0;
}
