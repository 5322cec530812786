// Light selection (proportional to emitted power, CDF in the lights buffer) and sampling of a
// point on the chosen light. Area lights emit from the front face of their triangles only.
#ifndef VKTG_LIGHTS_GLSL
#define VKTG_LIGHTS_GLSL
#include "lib/specialization.glsl"
#include "lib/warp.glsl"

struct LightSample {
  vec3 position;
  vec3 normal;     // area lights: front-face normal; point lights: unused
  float emission;  // area: radiance Le; point: intensity I
  float pdf;       // area: density per unit area including selection; point: selection probability
  bool isPoint;
  uint index;        // entry of the lights array
  uint triangle;     // area lights: the triangle (BVH order)
  vec2 barycentrics; // area lights: the material point (derivative passes move it with its triangle)
};

uint selectLight(float u) {
  uint lo = 0u, hi = frame.sceneCounts.y - 1u;
  while (lo < hi) {
    uint mid = (lo + hi) / 2u;
    if (lights[mid].cdf > u) hi = mid; else lo = mid + 1u;
  }
  return lo;
}

vec3 triangleNormal(GpuTriangle t) {
  return normalize(cross(t.p1.xyz - t.p0.xyz, t.p2.xyz - t.p0.xyz));
}

bool sampleLight(vec3 u, out LightSample ls) {
  ls.index = selectLight(u.x);
  GpuLight light = lights[ls.index];
  ls.isPoint = sceneHasLightType(kLightPoint) && light.type == kLightPoint;
  if (ls.isPoint) {
    ls.position = pointLightPosition(ls.index, light.positionIntensity.xyz);
    ls.normal = vec3(0.0);
    ls.emission = light.positionIntensity.w;
    ls.pdf = light.pmf;
    ls.triangle = 0xffffffffu;
    ls.barycentrics = vec2(0.0);
    return ls.pdf > 0.0;
  }
  GpuTriangle t = loadTriangle(light.triangle);
  vec2 b = sampleTriangleBarycentrics(u.yz);
  ls.triangle = light.triangle;
  ls.barycentrics = b;
  ls.position = (1.0 - b.x - b.y) * t.p0.xyz + b.x * t.p1.xyz + b.y * t.p2.xyz;
  ls.normal = triangleNormal(t);
  ls.emission = shapes[floatBitsToUint(t.p0.w)].emission;
  ls.pdf = light.pmf / t.p2.w;
  return ls.pdf > 0.0 && t.p2.w > 0.0;
}

// Area density (with selection) with which sampleLight lands on a point of an emissive triangle:
// pmf / area = (pi Le area / total power) / area.
float areaLightPdf(float emission) { return kPi * emission / frame.sceneInfo.z; }
#endif
