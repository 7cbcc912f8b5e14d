# Every dependency is a Debian 12 package (tools/setup.sh installs them).
find_package(Vulkan 1.3 REQUIRED)
find_package(Eigen3 3.4 REQUIRED NO_MODULE)
find_package(OpenCV 4.6 REQUIRED COMPONENTS core imgproc imgcodecs calib3d features2d line_descriptor ximgproc)
find_package(Ceres 2.1 REQUIRED)
find_package(TBB REQUIRED)
find_package(yaml-cpp REQUIRED)
find_package(spdlog REQUIRED)
find_package(fmt REQUIRED)
find_package(CLI11 REQUIRED)
find_package(nlohmann_json 3 REQUIRED)
find_package(Protobuf REQUIRED)
find_package(Threads REQUIRED)
if(VKVO_BUILD_TESTS)
  find_package(GTest REQUIRED)
endif()
if(VKVO_BUILD_BENCHMARKS)
  find_package(benchmark REQUIRED)
endif()

find_package(ONNX REQUIRED)   # libonnx-dev: generated protobuf classes, target onnx_proto

find_program(GLSLC_EXECUTABLE glslc REQUIRED)
find_program(SPIRV_VAL_EXECUTABLE spirv-val REQUIRED)
