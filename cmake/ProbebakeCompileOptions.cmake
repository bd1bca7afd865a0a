# Warnings and sanitizers, applied per target with probebake_target_defaults(<target>).
function(probebake_target_defaults target)
  if(CMAKE_CXX_COMPILER_ID MATCHES "GNU|Clang")
    target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow -Wconversion
                                             -Wno-sign-conversion -Wnon-virtual-dtor)
    if(PROBEBAKE_WERROR)
      target_compile_options(${target} PRIVATE -Werror)
    endif()
  endif()
endfunction()

if(PROBEBAKE_SANITIZE)
  add_compile_definitions(PROBEBAKE_SANITIZED=1)
  add_compile_options(-fsanitize=${PROBEBAKE_SANITIZE} -fno-omit-frame-pointer -fno-sanitize-recover=all)
  add_link_options(-fsanitize=${PROBEBAKE_SANITIZE})
endif()

# Fuzzing builds instrument every library for coverage (the fuzz targets add the libFuzzer main). UBSan
# must not recover, or libFuzzer would count undefined behaviour as a pass.
if(PROBEBAKE_BUILD_FUZZERS AND CMAKE_CXX_COMPILER_ID MATCHES "Clang")
  add_compile_options(-fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer)
  add_link_options(-fsanitize=address,undefined)
endif()
