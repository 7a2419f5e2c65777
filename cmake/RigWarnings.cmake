# Warnings as errors for our code, and the sanitizer flags of this build tree.
add_library(rig_warnings INTERFACE)
target_compile_options(rig_warnings INTERFACE
  -Wall -Wextra -Wpedantic -Werror -Wshadow -Wnon-virtual-dtor -Wold-style-cast -Wcast-align
  -Woverloaded-virtual -Wimplicit-fallthrough -Wno-missing-field-initializers)

if(RIG_SANITIZE)
  string(REPLACE "," ";" _sanitizers "${RIG_SANITIZE}")
  set(_flags "-fsanitize=${RIG_SANITIZE}" -fno-omit-frame-pointer -fno-sanitize-recover=all)
  # GCC 12 reports false -Wmaybe-uninitialized inside libstdc++ (std::regex, std::function)
  # when sanitizers instrument -O1 code; the release tree keeps that warning as an error.
  add_compile_options(${_flags} -O1 -Wno-maybe-uninitialized)
  add_link_options(${_flags})
endif()

# rig_target(NAME) applies the project's standard settings.
function(rig_target name)
  target_link_libraries(${name} PRIVATE rig_warnings)
endfunction()
