// Preloaded into sanitizer test runs (tests/CMakeLists.txt): keeps the Vulkan driver and the
// validation layer mapped for the whole process, so that heap blocks only their globals point to
// do not look leaked once the loader unloads them (LeakSanitizer scans mapped memory only).
//
// It opens them itself, RTLD_LOCAL and RTLD_NODELETE, rather than being given them in LD_PRELOAD:
// a preloaded validation layer's exported vkGetInstanceProcAddr and vkCreateInstance interpose
// the loader's for the whole process, and the layer then reported objects left at device
// destruction to its own log instead of the application's messenger, so a sanitizer run could not
// see a validation error. Opened locally, nothing is interposed; the loader's later dlopen of the
// same file returns this mapping, and its dlclose leaves it in place.
#include <dlfcn.h>

#include <cstdio>
#include <initializer_list>

namespace {

[[gnu::constructor]] void keepVulkanLibrariesLoaded() {
  for (const char* path : {VKTG_KEEP_LOADED_LIBRARIES}) {
    if (!dlopen(path, RTLD_NOW | RTLD_LOCAL | RTLD_NODELETE))
      std::fprintf(stderr, "keep_loaded: cannot open %s: %s\n", path, dlerror());
  }
}

}  // namespace
