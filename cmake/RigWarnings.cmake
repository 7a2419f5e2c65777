# Warnings as errors for our code, and the sanitizer flags of this build tree.
add_library(rig_warnings INTERFACE)
target_compile_options(rig_warnings INTERFACE
  -Wall -Wextra -Wpedantic -Werror -Wshadow -Wnon-virtual-dtor -Wold-style-cast -Wcast-align
  -Woverloaded-virtual -Wimplicit-fallthrough -Wno-missing-field-initializers)

if(RIG_SANITIZE)
  string(REPLACE "," ";" _sanitizers "${RIG_SANITIZE}")
  set(_flags "-fsanitize=${RIG_SANITIZE}" -fno-omit-frame-pointer -fno-sanitize-recover=all)
  if("undefined" IN_LIST _sanitizers)
    # UBSan's vptr check (dynamic type of every polymorphic access) nearly doubles the compile
    # time of Beast/Asio code: rig_service's Beast batch took 121 s of CPU with it, 67 s
    # without. Every other UBSan check stays on.
    list(APPEND _flags -fno-sanitize=vptr)
  endif()
  # GCC 12 reports false -Wmaybe-uninitialized inside libstdc++ (std::regex, std::function)
  # when sanitizers instrument -O1 code; the release tree keeps that warning as an error.
  # -g1 (line tables): sanitizer reports keep file:line, and Beast/JSON-heavy files compile a
  # quarter faster than with full -g (sessions.cpp under ASan+UBSan: 75 s against 99 s).
  add_compile_options(${_flags} -O1 -g1)
  if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
    add_compile_options(-Wno-maybe-uninitialized)
  endif()
  add_link_options(${_flags})
endif()

if(RIG_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
    message(FATAL_ERROR "RIG_FUZZ needs clang (libFuzzer): -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_C_COMPILER=clang")
  endif()
  add_compile_options(-fsanitize=fuzzer-no-link)
endif()

# rig_target(NAME) applies the project's standard settings.
function(rig_target name)
  target_link_libraries(${name} PRIVATE rig_warnings)
endfunction()
