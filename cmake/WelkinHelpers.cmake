# Compiler warnings for welkin's own code (not for third-party headers).
function(welkin_warnings target)
  # -Wno-restrict: GCC 12 false positives in std::string concatenation (GCC bug 105329).
  if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
    target_compile_options(${target} PRIVATE -Wall -Wextra -Werror -Wno-missing-field-initializers -Wno-restrict)
  else()  # clang (the fuzz build): no GCC-only flags
    target_compile_options(${target} PRIVATE -Wall -Wextra -Werror -Wno-missing-field-initializers)
  endif()
endfunction()

if(WELKIN_FUZZ)
  # Everything (the engine too) instrumented for libFuzzer's coverage and the sanitizers; the
  # fuzz targets add -fsanitize=fuzzer to their link. -O1 with line tables: quick to build,
  # readable stacks. NDEBUG off: the assertions are checks too.
  add_compile_options(-fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer
                      -O1 -gline-tables-only -UNDEBUG)
  add_link_options(-fsanitize=address,undefined)
endif()

if(WELKIN_SANITIZE)
  add_compile_options(-fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined)
  add_link_options(-fsanitize=address,undefined)
endif()

# welkin_embed_shaders(<target> <name> <base_dir> <files...>)
# Embeds GLSL files into <target>. Generates the header <welkin/embedded/<name>.hpp> declaring
#   std::string_view welkin::embedded::<name>(std::string_view relativePath);
# which returns the file text (throws welkin::Error naming the path if unknown).
set(WELKIN_EMBED_SCRIPT ${CMAKE_CURRENT_LIST_DIR}/EmbedShaders.cmake)
function(welkin_embed_shaders target name base_dir)
  set(files ${ARGN})
  set(out_dir ${CMAKE_CURRENT_BINARY_DIR}/embedded)
  set(out_hpp ${out_dir}/include/welkin/embedded/${name}.hpp)
  set(out_cpp ${out_dir}/${name}_embedded.cpp)
  set(abs_files)
  set(inc_files)
  foreach(f ${files})
    get_filename_component(af ${f} ABSOLUTE BASE_DIR ${base_dir})
    list(APPEND abs_files ${af})
    # A file's `#include "x"` (EmbedShaders.cmake expands it from the file's folder, which may be
    # another folder's shared file: ../../../engine/shaders/...) re-embeds when x changes.
    file(STRINGS ${af} _incs REGEX "^#include \"[^\"]+\"")
    get_filename_component(_dir ${af} DIRECTORY)
    foreach(line ${_incs})
      string(REGEX REPLACE "^#include \"([^\"]+)\".*" "\\1" _inc "${line}")
      get_filename_component(_abs ${_inc} ABSOLUTE BASE_DIR ${_dir})
      list(APPEND inc_files ${_abs})
    endforeach()
  endforeach()
  list(REMOVE_DUPLICATES inc_files)
  string(REPLACE ";" "|" files_arg "${abs_files}")
  add_custom_command(OUTPUT ${out_cpp} ${out_hpp}
    COMMAND ${CMAKE_COMMAND} -DNAME=${name} -DBASE=${base_dir} "-DFILES=${files_arg}"
            -DOUT_CPP=${out_cpp} -DOUT_HPP=${out_hpp} -P ${WELKIN_EMBED_SCRIPT}
    DEPENDS ${abs_files} ${inc_files} ${WELKIN_EMBED_SCRIPT}
    COMMENT "Embedding shaders for ${name}" VERBATIM)
  target_sources(${target} PRIVATE ${out_cpp} ${out_hpp})
  target_include_directories(${target} PUBLIC $<BUILD_INTERFACE:${out_dir}/include>)
endfunction()

# Public headers and internals (docs/architecture.md, "Installed API"). Every header under an
# include/ folder is installed except those listed here: implementation details that no installed
# header includes (scripts/check-installed-headers.sh fails CI if one does). An internal header
# that an installed one must include lives under a detail/ folder instead: installed, left out of
# the API reference (docs/Doxyfile).
set(WELKIN_INTERNAL_HEADERS
  welkin/check.hpp                        # precondition messages of the library's own checks
  welkin/glsl_cpp.hpp                     # the C++ side of the shared GLSL maths (*.shared.glsl)
  welkin/astro/elp.hpp                    # the Moon's series behind astro/bodies.hpp
  welkin/astro/vsop87.hpp                 # the planets' series behind astro/bodies.hpp
  welkin/generators/cloud_noise.hpp       # the Clouds element's noise textures
  welkin/generators/cloud_path_lut.hpp    # the Clouds element's ray-entry LUT
  welkin/generators/mie.hpp               # Lorenz-Mie series behind mie_tables.hpp
)

# welkin_install_headers(<include_dir>): installs the public headers under <include_dir>
# (keeping their paths below it) into ${CMAKE_INSTALL_INCLUDEDIR}, component "headers".
function(welkin_install_headers root)
  file(GLOB_RECURSE headers CONFIGURE_DEPENDS RELATIVE ${root} ${root}/*.hpp ${root}/*.h)
  foreach(h ${headers})
    if(h IN_LIST WELKIN_INTERNAL_HEADERS)
      set_property(GLOBAL APPEND PROPERTY WELKIN_INTERNAL_HEADERS_FOUND ${h})
    else()
      get_filename_component(dir ${h} DIRECTORY)
      install(FILES ${root}/${h} DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/${dir} COMPONENT headers)
    endif()
  endforeach()
endfunction()

# After every include folder was installed: a name in WELKIN_INTERNAL_HEADERS that no folder has
# is a stale entry (a header renamed or removed), an error rather than a silent no-op.
function(welkin_check_internal_headers)
  get_property(found GLOBAL PROPERTY WELKIN_INTERNAL_HEADERS_FOUND)
  foreach(h ${WELKIN_INTERNAL_HEADERS})
    if(NOT h IN_LIST found)
      message(FATAL_ERROR "WELKIN_INTERNAL_HEADERS (cmake/WelkinHelpers.cmake): ${h} is in no include/ folder")
    endif()
  endforeach()
endfunction()

# Writes CONTENT to FILE only when it differs from what is there, so a reconfigure that generates
# the same text does not touch the file (and rebuild what includes it).
function(welkin_write_if_changed file content)
  set(old "")
  if(EXISTS ${file})
    file(READ ${file} old)
  endif()
  if(NOT old STREQUAL content)
    file(WRITE ${file} "${content}")
  endif()
endfunction()
