// The macros of the headers that C++ and GLSL share (gpu_types.h, runtime_types.h, memory_types.h,
// leaf_rule.h, bindings.h and the runtime's *_bindings.h): in C++ their declarations live in namespace
// probebake::gpu, constants are inline constexpr and functions inline; in GLSL they are plain. Defined here
// once and never undefined (the names are the project's own).
#ifndef PROBEBAKE_GPU_SHARED_H
#define PROBEBAKE_GPU_SHARED_H

#ifdef __cplusplus
#include <cstdint>

#define PB_GPU_BEGIN                                                                                                   \
  namespace probebake::gpu {                                                                                           \
  using uint = std::uint32_t;
#define PB_GPU_END }
#define PB_CONSTANT(type, name, value) inline constexpr type name = value
#define PB_FUNCTION inline
#else
#define PB_GPU_BEGIN
#define PB_GPU_END
#define PB_CONSTANT(type, name, value) const type name = value
#define PB_FUNCTION
#endif

#endif // PROBEBAKE_GPU_SHARED_H
