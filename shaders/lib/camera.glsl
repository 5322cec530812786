// The camera as the end of a connection (light-tracing style): what a point seen along a given
// direction contributes to, and where. Needs lib/common.glsl and lib/bindings.glsl (frame) and
// lib/specialization.glsl.
#ifndef VKTG_CAMERA_GLSL
#define VKTG_CAMERA_GLSL

// The camera's importance per unit solid angle for a ray leaving it along unit `dir`, and the
// pixel it falls in (kNoPixel and 0 outside the image or behind the sensor), in the current view
// (lib/view.glsl). A pinhole pixel
// averages radiance over its footprint on the image plane at distance 1 (area 4 |R| |U| / pixels,
// solid angle cos^3 per unit area); the point sensor measures irradiance (cos per solid angle).
float cameraImportance(vec3 dir, out uint pixel) {
  pixel = kNoPixel;
  float c = dot(dir, cameraForward());
  if (!(c > 0.0)) return 0.0;
  if (kSpecCameraTypeValue == kCameraPointSensor) {
    pixel = imagePixel(0u);
    return c;
  }
  vec3 q = dir / c;
  vec3 r = cameraRight(), u = cameraUp();
  float px = 0.5 * (dot(q, r) / dot(r, r) + 1.0);
  float py = 0.5 * (1.0 - dot(q, u) / dot(u, u));
  if (!(px >= 0.0 && px < 1.0 && py >= 0.0 && py < 1.0)) return 0.0;
  uint width = frame.image.x, height = frame.viewInfo.y;
  uint x = min(uint(px * float(width)), width - 1u);
  uint y = min(uint(py * float(height)), height - 1u);
  pixel = imagePixel(y * width + x);
  return float(width * height) / (4.0 * length(r) * length(u) * c * c * c);
}

#endif
