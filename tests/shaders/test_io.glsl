// Input/output of GPU test kernels (see tests/support/gpu_test.h).
layout(std430, set = 0, binding = kBindingTestIn) readonly buffer TestInBlock { uint testIn[]; };
layout(std430, set = 0, binding = kBindingTestOut) buffer TestOutBlock { uint testOut[]; };
layout(push_constant) uniform TestPush { uint invocationCount; };
layout(local_size_x = kWorkgroupSize) in;
