// The one translation unit that compiles tinygltf's implementation (loader and writer), shared by the scene
// loader (bake/) and the sample writer (samples/). Everything else includes <tiny_gltf.h> without these macros.
//
// stb_image / stb_image_write are NOT implemented here: Debian's libstb (pkg-config `stb`, linked through
// probebake_tinygltf) already provides their definitions, and defining them again would clash at link time.
#define TINYGLTF_IMPLEMENTATION
// TINYGLTF_ENABLE_DRACO stays off: tinygltf's Draco path indexes bufferViews unchecked and ignores decode
// failures; the loader decodes KHR_draco_mesh_compression itself (scene/src/gltf_draco.cpp).
#include <tiny_gltf.h>
