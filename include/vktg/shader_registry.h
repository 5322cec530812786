// Embedded SPIR-V, compiled from shaders/*.comp at build time. Names equal pass names.
#pragma once
#include <cstdint>
#include <map>
#include <span>
#include <string>

namespace vktg {
using ShaderTable = std::map<std::string, std::span<const uint32_t>, std::less<>>;
extern const ShaderTable kShaderRegistry;       // production passes
extern const ShaderTable kTestShaderRegistry;   // test kernels (linked into tests only)
}  // namespace vktg
