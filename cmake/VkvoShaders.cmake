# The shader table (shaders/CMakeLists.txt) lists every op: its GLSL source, the defines that make it, its
# push-constant struct, the precisions it is compiled for and any device feature it needs. From it the build
#   - compiles each op once per listed precision (glslc -DVKVO_VARIANT_<precision>=1; once without a precision define
#     where none is listed) and validates it with spirv-val,
#   - embeds the SPIR-V words in the binary with the interface reflected from them (shaders/gen/spirv_embed.cpp:
#     binding kinds and access, push-constant size, checked against the C++ struct at compile time),
#   - generates runtime/shader_op.hpp (enum class Op, one enumerator per op) and the table of ops and variants.
# Precisions (shaders/include/precision.glsl):
#   fp32  : fp32 storage, fp32 math
#   fp16s : fp16 storage, fp32 math   (fast path on devices that emulate fp16 math, e.g. lavapipe)
#   fp16  : fp16 storage, fp16 math with fp32 accumulation where the op needs it
set(VKVO_ALL_PRECISIONS fp32 fp16s fp16)
# Device features a variant may need beyond what every Vulkan 1.1 device has (runtime/shader_registry.hpp).
set(VKVO_SHADER_FEATURES int64 cooperative_matrix)

# vkvo_shader(<op> [SOURCE <file.comp>] [DEFINES <NAME=VALUE>...] [PUSH <Struct>] [PRECISIONS <precision>...]
#             [REQUIRES <feature>])
# SOURCE defaults to <op>.comp; several ops may share a source with different DEFINES. PUSH names the struct of
# shaders/include/push/ the shader's push-constant block is declared with. PRECISIONS: the storage precisions the op
# runs at (its source includes precision.glsl); none: the op is precision-independent and compiled once.
function(vkvo_shader op)
  cmake_parse_arguments(ARG "" "SOURCE;PUSH;REQUIRES" "DEFINES;PRECISIONS" ${ARGN})
  if(ARG_UNPARSED_ARGUMENTS)
    message(FATAL_ERROR "vkvo_shader(${op}): unknown arguments ${ARG_UNPARSED_ARGUMENTS}")
  endif()
  get_property(ops GLOBAL PROPERTY VKVO_SHADER_OPS)
  if(op IN_LIST ops)
    message(FATAL_ERROR "vkvo_shader(${op}): listed twice")
  endif()
  foreach(precision ${ARG_PRECISIONS})
    if(NOT precision IN_LIST VKVO_ALL_PRECISIONS)
      message(FATAL_ERROR "vkvo_shader(${op}): unknown precision ${precision}")
    endif()
  endforeach()
  if(ARG_REQUIRES AND NOT ARG_REQUIRES IN_LIST VKVO_SHADER_FEATURES)
    message(FATAL_ERROR "vkvo_shader(${op}): unknown feature ${ARG_REQUIRES} (known: ${VKVO_SHADER_FEATURES})")
  endif()
  if(NOT ARG_SOURCE)
    set(ARG_SOURCE ${op}.comp)
  endif()
  set_property(GLOBAL APPEND PROPERTY VKVO_SHADER_OPS ${op})
  set_property(GLOBAL PROPERTY VKVO_SHADER_${op}_SOURCE ${ARG_SOURCE})
  set_property(GLOBAL PROPERTY VKVO_SHADER_${op}_DEFINES ${ARG_DEFINES})
  set_property(GLOBAL PROPERTY VKVO_SHADER_${op}_PUSH ${ARG_PUSH})
  set_property(GLOBAL PROPERTY VKVO_SHADER_${op}_PRECISIONS ${ARG_PRECISIONS})
  set_property(GLOBAL PROPERTY VKVO_SHADER_${op}_REQUIRES ${ARG_REQUIRES})
endfunction()

# vkvo_compile_shaders(<target> SOURCE_DIR <dir>): a static library of every op of the table.
function(vkvo_compile_shaders target)
  cmake_parse_arguments(ARG "" "SOURCE_DIR" "" ${ARGN})
  file(GLOB_RECURSE shader_headers CONFIGURE_DEPENDS ${ARG_SOURCE_DIR}/include/*)
  set(gen_dir ${CMAKE_CURRENT_BINARY_DIR}/spirv)
  set(gen_include ${CMAKE_CURRENT_BINARY_DIR}/include)
  add_executable(vkvo_spirv_embed ${ARG_SOURCE_DIR}/gen/spirv_embed.cpp)
  vkvo_set_warnings(vkvo_spirv_embed)

  get_property(ops GLOBAL PROPERTY VKVO_SHADER_OPS)
  set(embedded_sources "")
  set(enumerators "")
  set(op_entries "")
  set(variant_entries "")
  set(declarations "")
  foreach(op ${ops})
    get_property(source GLOBAL PROPERTY VKVO_SHADER_${op}_SOURCE)
    get_property(defines GLOBAL PROPERTY VKVO_SHADER_${op}_DEFINES)
    get_property(push GLOBAL PROPERTY VKVO_SHADER_${op}_PUSH)
    get_property(precisions GLOBAL PROPERTY VKVO_SHADER_${op}_PRECISIONS)
    get_property(requires GLOBAL PROPERTY VKVO_SHADER_${op}_REQUIRES)
    set(src ${ARG_SOURCE_DIR}/${source})
    if(NOT EXISTS ${src})
      message(FATAL_ERROR "shader table: ${op}: no source ${src}")
    endif()
    set(define_flags "")
    foreach(define ${defines})
      list(APPEND define_flags -D${define})
    endforeach()
    string(APPEND enumerators "  ${op},\n")
    set(mask "0u")
    foreach(precision ${precisions})
      string(APPEND mask " | precision_bit(Precision::${precision})")
    endforeach()
    if(requires)
      set(feature "ShaderFeature::${requires}")
    else()
      set(feature "ShaderFeature::none")
    endif()
    string(APPEND op_entries "    {\"${op}\", ${mask}, ${feature}},\n")

    set(variants ${precisions})
    if(NOT variants)
      set(variants any)
    endif()
    foreach(variant ${variants})
      set(spv ${gen_dir}/${op}.${variant}.spv)
      set(cpp ${gen_dir}/${op}.${variant}.cpp)
      string(MAKE_C_IDENTIFIER "spirv_${op}_${variant}" symbol)
      if(variant STREQUAL "any")
        set(variant_flags "")
        set(precision_value "std::nullopt")
      else()
        set(variant_flags -DVKVO_VARIANT_${variant}=1)
        set(precision_value "Precision::${variant}")
      endif()
      add_custom_command(
        OUTPUT ${cpp}
        COMMAND ${CMAKE_COMMAND} -E make_directory ${gen_dir}
        COMMAND ${GLSLC_EXECUTABLE} -fshader-stage=compute --target-env=vulkan1.1 -O -Werror
                -I ${ARG_SOURCE_DIR}/include ${variant_flags} ${define_flags} -o ${spv} ${src}
        COMMAND ${SPIRV_VAL_EXECUTABLE} --target-env vulkan1.1 ${spv}
        COMMAND vkvo_spirv_embed ${spv} ${cpp} ${symbol} ${push}
        DEPENDS ${src} ${shader_headers} vkvo_spirv_embed
        COMMENT "glslc + spirv-val: ${op} (${variant})"
        VERBATIM)
      list(APPEND embedded_sources ${cpp})
      string(APPEND declarations "extern const std::uint32_t ${symbol}_words[];\n"
                                 "extern const std::size_t ${symbol}_word_count;\n"
                                 "extern const ShaderInterface ${symbol}_interface;\n")
      string(APPEND variant_entries
             "    {Op::${op}, ${precision_value}, ${symbol}_words, ${symbol}_word_count, &${symbol}_interface},\n")
    endforeach()
  endforeach()
  list(LENGTH ops op_count)
  configure_file(${PROJECT_SOURCE_DIR}/cmake/shader_op.hpp.in ${gen_include}/runtime/shader_op.hpp @ONLY)
  set(table_cpp ${gen_dir}/shader_table.cpp)
  configure_file(${PROJECT_SOURCE_DIR}/cmake/shader_table.cpp.in ${table_cpp} @ONLY)
  add_library(${target} STATIC ${embedded_sources} ${table_cpp})
  target_include_directories(${target} PUBLIC $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}>
                                              $<BUILD_INTERFACE:${gen_include}>
                                              $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}/vkvo>)
  install(FILES ${gen_include}/runtime/shader_op.hpp DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/vkvo/runtime)
endfunction()
