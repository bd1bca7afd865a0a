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
  add_compile_options(-fsanitize=${PROBEBAKE_SANITIZE} -fno-omit-frame-pointer -fno-sanitize-recover=all)
  add_link_options(-fsanitize=${PROBEBAKE_SANITIZE})
endif()
