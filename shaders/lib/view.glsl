// The view an invocation works for. A render may hold several views of one scene (the scan points
// of a confocal capture, the targets of an optimisation): one gate, sample count and image size,
// each with its own camera pose, point-light positions and seed. Their images are stacked as rows
// of one tall image, view v owning pixels [v P, (v + 1) P), so films, adjoint images and the
// accumulation passes see a single image; only what reads a camera or point-light position,
// meets the gate (a view's path offset) or keys a random number asks this file. Random numbers are keyed by the view's own pixel, sample
// and seed, so a view renders exactly as it would alone. With kSpecMultiView off (one view) all of
// it comes from the frame block and compiles to what it was before views existed.
//
// A view record in frameViews (frame.viewInfo.z vec4s): position (w: seed bits), forward (w: path
// offset), right, up as in FrameUniforms, then one position per point light.
#ifndef VKTG_VIEW_GLSL
#define VKTG_VIEW_GLSL

// The current invocation's view: each pass sets it from its path (PathState.misc.z) or its
// sample index before it reads anything below. A global, so that the camera and light accessors
// deep in the libraries need no extra argument.
uint gView = 0u;

bool multiView() { return kSpecMultiViewValue != 0u; }
uint viewRecord() { return gView * frame.viewInfo.z; }

uint pixelsPerView() { return frame.image.x * frame.viewInfo.y; }
// Splatted renders (edges, connections from the camera): samples per view are frame.image.z.
void setViewOfPixel(uint pixel) { gView = multiView() ? pixel / pixelsPerView() : 0u; }
void setViewOfSample(uint sampleIndex) { gView = multiView() ? sampleIndex / frame.image.z : 0u; }
void setViewOfPath(PathState ps) { gView = multiView() ? floatBitsToUint(ps.misc.z) : 0u; }
float viewBits() { return uintBitsToFloat(gView); }

vec3 cameraPosition() { return multiView() ? frameViews[viewRecord()].xyz : frame.cameraPosition.xyz; }
vec3 cameraForward() { return multiView() ? frameViews[viewRecord() + 1u].xyz : frame.cameraForward.xyz; }
vec3 cameraRight() { return multiView() ? frameViews[viewRecord() + 2u].xyz : frame.cameraRight.xyz; }
vec3 cameraUp() { return multiView() ? frameViews[viewRecord() + 3u].xyz : frame.cameraUp.xyz; }
// Optical path outside the scene that this view's paths count (lib/gate.glsl); forward's w.
float viewPathOffset() { return multiView() ? frameViews[viewRecord() + 1u].w : frame.cameraForward.w; }
uint viewSeed() { return multiView() ? floatBitsToUint(frameViews[viewRecord()].w) : frame.image.w; }

// Random-number keys: the pixel within its view (kNoPixel stays), and a splatted sample's index
// within its view.
uint viewPixel(uint pixel) { return pixel == kNoPixel ? pixel : pixel - gView * pixelsPerView(); }
uint viewSample(uint sampleIndex) { return sampleIndex - gView * frame.image.z; }
// The image pixel of pixel `local` of the current view.
uint imagePixel(uint local) { return local + gView * pixelsPerView(); }

// Point light `light` (a lights[] index) as this view places it; `stored` is where lights[] has it.
vec3 pointLightPosition(uint light, vec3 stored) {
  return multiView() ? frameViews[viewRecord() + 4u + light - frame.viewInfo.w].xyz : stored;
}
#endif
