// The adjoint passes' per-path records (include/vktg/gpu/shared.h): the tape of path vertices and
// what each queued connection's vertices are. Vertex `depth` of path `path` is
// tape[depth * batch + path]; entry 0 (the camera or sensor) also counts the surface vertices.
#ifndef VKTG_TAPE_GLSL
#define VKTG_TAPE_GLSL

layout(std430, set = 0, binding = kBindingTape) buffer TapeBlock { TapeVertex tape[]; };
layout(std430, set = 0, binding = kBindingShadowAdjoint) buffer ShadowAdjointBlock { ShadowAdjoint shadowAdjoint[]; };

uint tapeIndex(uint depth, uint path) { return depth * frame.pathInfo.w + path; }

uint tapeLength(uint path) { return floatBitsToUint(tape[tapeIndex(0u, path)].adjoint.z); }

// A path vertex as the tape reconstructs it: the camera (or sensor) at depth 0, else the exact
// surface point of the stored hit, with its normal and material.
struct TapePoint {
  vec3 position;
  vec3 normal;
  uint triangle;  // ~0 at the camera
  vec2 uv;
  uint material;
  float ior;      // of the medium the segment arriving here ran in
};

TapePoint tapePoint(uint depth, uint path) {
  TapeVertex v = tape[tapeIndex(depth, path)];
  TapePoint p;
  p.triangle = floatBitsToUint(v.hit.x);
  p.uv = v.hit.yz;
  p.ior = v.hit.w;
  if (depth == 0u) {
    p.position = cameraPosition();
    p.normal = cameraForward();
    p.material = 0u;
    return p;
  }
  SurfacePoint sp = surfacePoint(p.triangle, p.uv);
  p.position = sp.position;
  p.normal = sp.normal;
  p.material = shapes[sp.shape].material;
  return p;
}

// Whether vertex `depth` is a first hit kept on its camera ray (behind a pinhole).
bool onCameraRay(uint depth) { return depth == 1u && kSpecCameraTypeValue == kCameraPerspective; }
#endif
