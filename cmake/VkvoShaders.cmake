# Compiles every GLSL compute shader to SPIR-V once per precision variant, validates it with spirv-val and
# embeds the words in a C++ table, so the binary needs no shader files at run time.
#   fp32  : fp32 storage, fp32 math
#   fp16s : fp16 storage, fp32 math   (fast path on devices that emulate fp16 math, e.g. lavapipe)
#   fp16  : fp16 storage, fp16 math with fp32 accumulation where the op needs it
set(VKVO_SHADER_VARIANTS fp32 fp16s fp16)

function(vkvo_compile_shaders target)
  cmake_parse_arguments(ARG "" "SOURCE_DIR" "" ${ARGN})
  file(GLOB shader_sources CONFIGURE_DEPENDS ${ARG_SOURCE_DIR}/*.comp)
  file(GLOB shader_headers CONFIGURE_DEPENDS ${ARG_SOURCE_DIR}/include/*.glsl)
  set(gen_dir ${CMAKE_CURRENT_BINARY_DIR}/spirv)
  set(embedded_sources "")
  set(table_entries "")
  set(declarations "")
  foreach(src ${shader_sources})
    get_filename_component(op ${src} NAME_WE)
    foreach(variant ${VKVO_SHADER_VARIANTS})
      set(spv ${gen_dir}/${op}.${variant}.spv)
      set(cpp ${gen_dir}/${op}.${variant}.cpp)
      string(MAKE_C_IDENTIFIER "spirv_${op}_${variant}" symbol)
      add_custom_command(
        OUTPUT ${cpp}
        COMMAND ${CMAKE_COMMAND} -E make_directory ${gen_dir}
        COMMAND ${GLSLC_EXECUTABLE} -fshader-stage=compute --target-env=vulkan1.1 -O -Werror
                -I ${ARG_SOURCE_DIR}/include -DVKVO_VARIANT_${variant}=1 -o ${spv} ${src}
        COMMAND ${SPIRV_VAL_EXECUTABLE} --target-env vulkan1.1 ${spv}
        COMMAND ${CMAKE_COMMAND} -DINPUT=${spv} -DOUTPUT=${cpp} -DSYMBOL=${symbol}
                -P ${PROJECT_SOURCE_DIR}/cmake/EmbedSpirv.cmake
        DEPENDS ${src} ${shader_headers} ${PROJECT_SOURCE_DIR}/cmake/EmbedSpirv.cmake
        COMMENT "glslc + spirv-val: ${op} (${variant})"
        VERBATIM)
      list(APPEND embedded_sources ${cpp})
      string(APPEND declarations "extern const std::uint32_t ${symbol}[]; extern const std::size_t ${symbol}_words;\n")
      string(APPEND table_entries "    {\"${op}\", \"${variant}\", ${symbol}, ${symbol}_words},\n")
    endforeach()
  endforeach()
  set(table_cpp ${gen_dir}/shader_table.cpp)
  configure_file(${PROJECT_SOURCE_DIR}/cmake/shader_table.cpp.in ${table_cpp} @ONLY)
  add_library(${target} STATIC ${embedded_sources} ${table_cpp})
  target_include_directories(${target} PUBLIC $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}>)
endfunction()
