# Compiles GLSL compute shaders with glslangValidator (target env vulkan1.2) at build time and
# embeds the SPIR-V in a static library with a lookup table `NAME` (see include/vktg/shader_registry.h).
#
# A source may declare variants on its first lines:   // vktg-variant: shade_d VKTG_DERIVATIVE=1
# Each variant is the same source compiled with the listed defines, registered under its own name.
function(vktg_embed_shaders target registry_name sources)
  set(gen_dir ${CMAKE_CURRENT_BINARY_DIR}/${target})
  file(MAKE_DIRECTORY ${gen_dir})
  set(headers "")
  set(includes "")
  set(entries "")
  foreach(src ${sources})
    get_filename_component(base ${src} NAME_WE)
    # Variant lines are read at configure time: re-configure when a shader changes.
    set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${src})
    file(STRINGS ${src} variant_lines REGEX "^// vktg-variant: ")
    set(variants "${base}|")
    foreach(line ${variant_lines})
      string(REGEX REPLACE "^// vktg-variant: " "" spec "${line}")
      string(REPLACE " " ";" spec_list "${spec}")
      list(POP_FRONT spec_list vname)
      string(REPLACE ";" "," vdefs "${spec_list}")
      list(APPEND variants "${vname}|${vdefs}")
    endforeach()
    foreach(variant ${variants})
      string(REPLACE "|" ";" parts "${variant}")
      list(GET parts 0 name)
      list(LENGTH parts nparts)
      set(define_args "")
      if(nparts GREATER 1)
        list(GET parts 1 defs)
        if(NOT defs STREQUAL "")
          string(REPLACE "," ";" defs_list "${defs}")
          foreach(d ${defs_list})
            list(APPEND define_args "-D${d}")
          endforeach()
        endif()
      endif()
      set(out ${gen_dir}/${name}.spv.h)
      # Run from the source tree with relative paths: the debug info (-g) names files relative to
      # the repository, so no source-tree path ends up in the binary.
      file(RELATIVE_PATH relative_src ${CMAKE_SOURCE_DIR} ${src})
      add_custom_command(
        OUTPUT ${out}
        COMMAND ${GLSLANG_VALIDATOR} -V --target-env vulkan1.2 -g -Os
                -Ishaders -Iinclude -Itests/shaders ${define_args}
                --vn kSpv_${name} --depfile ${out}.d -o ${out} ${relative_src}
        WORKING_DIRECTORY ${CMAKE_SOURCE_DIR}
        DEPENDS ${src}
        DEPFILE ${out}.d
        COMMENT "glslang ${name}"
        VERBATIM)
      list(APPEND headers ${out})
      string(APPEND includes "#include \"${name}.spv.h\"\n")
      string(APPEND entries "    {\"${name}\", {kSpv_${name}, sizeof(kSpv_${name}) / sizeof(uint32_t)}},\n")
    endforeach()
  endforeach()
  set(REGISTRY_NAME ${registry_name})
  set(SHADER_INCLUDES "${includes}")
  set(SHADER_ENTRIES "${entries}")
  configure_file(${CMAKE_SOURCE_DIR}/cmake/shader_registry.cpp.in ${gen_dir}/registry.cpp @ONLY)
  add_library(${target} STATIC ${gen_dir}/registry.cpp ${headers})
  target_include_directories(${target} PRIVATE ${gen_dir} PUBLIC ${CMAKE_SOURCE_DIR}/include)
endfunction()
