#version 460
#extension GL_GOOGLE_include_directive : require
// vktg-variant: generate_camera_rays_d VKTG_DERIVATIVE=1
// vktg-variant: generate_camera_rays_adj VKTG_ADJOINT=1
// Pass generate_camera_rays (_d: also zeroes the path's derivative lanes; _adj: starts the path's
// tape with the camera or sensor): starts one path per (pixel, sample) of the batch.
// Reads: frame (camera), push.args (x first pixel-sample index, w active paths).
// Writes: paths[i], ray queue 0 (+ its counter); at a point sensor also the shadow queue (NEE
// from the sensor itself: direct light and, in ellipsoidal mode, one-bounce connections).
// Dispatch: ceil(batch / kWorkgroupSize) groups.
#include "lib/common.glsl"
#include "lib/bindings.glsl"
#include "lib/rng.glsl"
#include "lib/nee.glsl"

layout(local_size_x = kWorkgroupSize) in;
layout(push_constant) uniform Push { PassPush push; };

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= push.args.w) return;
  uint pixels = frame.image.x * frame.image.y;  // of every view
  uint linear = push.args.x + i;
  uint pixel = linear % pixels;
  uint sampleIndex = push.args.y + linear / pixels;
  setViewOfPixel(pixel);
  uint local = viewPixel(pixel);
  Rng rng = rngCreate(local, sampleIndex, kRngDimCamera, viewSeed());
  vec4 u = rngNext4(rng);

#ifdef VKTG_DERIVATIVE
  for (uint lane = 0u; lane < kSpecLanesValue; ++lane)
    pathDerivs[i * kSpecLanesValue + lane] = PathDerivative(vec4(0.0), vec4(0.0));
#endif
#ifdef VKTG_ADJOINT
  tape[tapeIndex(0u, i)] = TapeVertex(vec4(uintBitsToFloat(0xffffffffu), 0.0, 0.0, 1.0), vec4(0.0));
#endif
  PathState ps;
  vec3 camera = cameraPosition(), forward = cameraForward();
  ps.position = vec4(camera, 0.0);
  ps.ids = uvec4(pixel, sampleIndex, 0u, 0u);
  ps.misc = vec4(0.0, 1.0, viewBits(), 0.0);
  ps.previous = vec4(camera, uintBitsToFloat(0xffffffffu));
  if (kSpecCameraTypeValue == kCameraPerspective) {
    float px = (float(local % frame.image.x) + u.x) / float(frame.image.x);
    float py = (float(local / frame.image.x) + u.y) / float(frame.viewInfo.y);
    vec3 dir = normalize(forward + (2.0 * px - 1.0) * cameraRight() + (1.0 - 2.0 * py) * cameraUp());
    ps.direction = vec4(dir, 0.0);
    ps.normal = vec4(forward, 1.0);
  } else {
    // Cosine-weighted direction about the sensor normal: importance cos / pdf = pi.
    vec3 n = forward;
    vec3 t, b;
    basisFromNormal(n, t, b);
    vec3 local = sampleCosineHemisphere(u.xy);
    vec3 dir = normalize(local.x * t + local.y * b + local.z * n);
    ps.direction = vec4(dir, 0.0);
    ps.normal = vec4(n, kPi);
    ps.misc.x = max(local.z, 0.0) * kInvPi;
    NeeVertex v;
    v.position = ps.position.xyz;
    v.normal = n;
    v.wi = n;
    v.isSensor = true;
    v.throughput = 1.0;
    v.len = 0.0;
    v.previousPosition = v.position;  // the sensor starts the path: nothing before it
    v.previousLen = 0.0;
    v.arrivalPdf = 0.0;
    v.triangle = 0xffffffffu;
    v.path = i;
    v.uv = vec2(0.0);
    v.materialIndex = 0u;
    v.rayForm = false;
    v.arrivalDir = n;
    v.firstEllipsoidVertex = frame.pathInfo.y;
    neeAtVertex(i, v, 0u, pixel, sampleIndex);
  }
  paths[i] = ps;
  uint slot = atomicAdd(counters[kCounterRays0], 1u);
  rayQueues[slot] = i;
}
