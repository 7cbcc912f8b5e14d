// `vkvo convert`: ONNX (SuperPoint or SuperGlue) -> .vkvopack model pack for the Vulkan networks.
#include <memory>
#include <optional>
#include <string>

#include <spdlog/spdlog.h>

#include "app/command.hpp"
#include "io/model_pack.hpp"
#include "tools/convert/convert.hpp"

namespace {

struct ConvertOptions {
  std::string onnx;
  std::string out;
  std::string kind = "auto";
};

vkvo::app::CommandRegistration registration{
    {"convert", "convert a SuperPoint or SuperGlue ONNX model into a .vkvopack model pack", [](CLI::App& sub) {
       auto opts = std::make_shared<ConvertOptions>();
       sub.add_option("--onnx", opts->onnx, "input ONNX model")->required()->check(CLI::ExistingFile);
       sub.add_option("--out", opts->out, "output model pack (.vkvopack)")->required();
       sub.add_option("--kind", opts->kind, "network kind; auto tells them apart by graph structure")
           ->check(CLI::IsMember({"auto", "superpoint", "superglue"}));
       return std::function<int()>([opts] {
         std::optional<vkvo::io::NetworkKind> kind;
         if (opts->kind == "superpoint") kind = vkvo::io::NetworkKind::superpoint;
         if (opts->kind == "superglue") kind = vkvo::io::NetworkKind::superglue;
         const auto summary = vkvo::convert::convert_file(opts->onnx, opts->out, kind);
         spdlog::info("{} -> {}: {} pack, {} tensors, {:.1f} MiB", opts->onnx, opts->out,
                      vkvo::io::to_string(summary.kind), summary.tensors, summary.bytes / (1024.0 * 1024.0));
         return 0;
       });
     }}};

}  // namespace
