#version 460
#extension GL_GOOGLE_include_directive : require
// Pass backprop_paths (adjoint): walks every path of the batch backwards along its tape once all
// its contributions are known. A contribution closed at vertex k (emission there, or a connection
// from it) carries every segment factor j <= k of the path's throughput and every segment length
// j <= k of its path length, so factor j is weighted by the sum of the value weights closed at
// vertices k >= j and segment j's optical length by the sum of their length weights (suffix sums,
// built on the way back). Vertex j's adjoint is complete once factor j is done (factors j, j+1
// and j+2 touch it), so it is scattered then: O(path length) work per path, whatever the number
// of parameters. The first hit behind a pinhole has no factor of its own (its pixel measures it)
// and moves along its camera ray.
// Reads: tape, scene. Writes: gradient accumulators. Dispatch: ceil(paths of the batch /
// kWorkgroupSize); push.args.w: paths in the batch.
#define VKTG_ADJOINT 1
#include "lib/common.glsl"
#include "lib/bindings.glsl"
#include "lib/nee.glsl"
#include "lib/adjoint.glsl"

layout(local_size_x = kWorkgroupSize) in;
layout(push_constant) uniform Push { PassPush push; };

void backpropPath() {
  uint path = gl_GlobalInvocationID.x;
  if (path >= push.args.w) return;
  uint n = tapeLength(path);
  if (n == 0u) return;
  setViewOfPath(paths[path]);
  float valueSuffix = 0.0, lengthSuffix = 0.0;
  // The window of the walk: x_j, x_{j-1}, x_{j-2} and their adjoints.
  TapePoint x = tapePoint(n, path), x1 = tapePoint(n - 1u, path);
  VertexAdjoint xBar = noAdjoint(), x1Bar = noAdjoint(), x2Bar = noAdjoint();
  for (uint j = n; j >= 1u; --j) {
    vec4 closed = tape[tapeIndex(j, path)].adjoint;
    valueSuffix += closed.x;
    lengthSuffix += closed.y;
    TapePoint x2 = j >= 2u ? tapePoint(j - 2u, path) : x1;
    if (valueSuffix != 0.0 || lengthSuffix != 0.0) {
      // Factor j: f at x_{j-1} (the sensor's constant importance at j = 1), both cosines, 1 / d^2
      // and the Jacobian of x_j; behind a pinhole the first segment has no factor.
      bool factor = !onCameraRay(j);
      Segment s = Segment(x2.position, x1.position, x.position, x1.normal, x.normal, x1.material, j >= 2u, true, true);
      segmentAdjoint(s, factor ? valueSuffix : 0.0, lengthSuffix * x.ior, x2Bar, x1Bar, xBar);
    }
    scatterSurfaceAdjoint(x.triangle, x.uv, xBar, onCameraRay(j));
    x = x1;
    x1 = x2;
    xBar = x1Bar;
    x1Bar = x2Bar;
    x2Bar = noAdjoint();
  }
}

void main() {
  backpropPath();
  countScatterFaults();
}
