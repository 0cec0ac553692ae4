# Compiler warnings for welkin's own code (not for third-party headers).
function(welkin_warnings target)
  # -Wno-restrict: GCC 12 false positives in std::string concatenation (GCC bug 105329).
  target_compile_options(${target} PRIVATE -Wall -Wextra -Werror -Wno-missing-field-initializers -Wno-restrict)
endfunction()

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
  foreach(f ${files})
    get_filename_component(af ${f} ABSOLUTE BASE_DIR ${base_dir})
    list(APPEND abs_files ${af})
  endforeach()
  string(REPLACE ";" "|" files_arg "${abs_files}")
  add_custom_command(OUTPUT ${out_cpp} ${out_hpp}
    COMMAND ${CMAKE_COMMAND} -DNAME=${name} -DBASE=${base_dir} "-DFILES=${files_arg}"
            -DOUT_CPP=${out_cpp} -DOUT_HPP=${out_hpp} -P ${WELKIN_EMBED_SCRIPT}
    DEPENDS ${abs_files} ${WELKIN_EMBED_SCRIPT}
    COMMENT "Embedding shaders for ${name}" VERBATIM)
  target_sources(${target} PRIVATE ${out_cpp} ${out_hpp})
  target_include_directories(${target} PUBLIC $<BUILD_INTERFACE:${out_dir}/include>)
endfunction()
