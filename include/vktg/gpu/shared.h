// Structs, bindings and constants shared by C++ and GLSL: the one definition of every GPU layout.
// Everything is std430 and built from 16-byte vec4/uvec4 members so both sides agree without
// padding rules; src/host/gpu_layout_checks.cpp static_asserts the sizes.
#ifndef VKTG_GPU_SHARED_H
#define VKTG_GPU_SHARED_H

#ifdef __cplusplus
#include <cstdint>
#include <glm/glm.hpp>
namespace vktg::gpu {
using vec4 = glm::vec4;
using uvec4 = glm::uvec4;
using uint = uint32_t;
#define VKTG_CONST(type, name, value) inline constexpr type name = value
#else
#define VKTG_CONST(type, name, value) const type name = value
#endif

VKTG_CONST(uint, kWorkgroupSize, 64);
// Buffers larger than maxStorageBufferRange are split into up to this many bindings.
VKTG_CONST(uint, kMaxBufferChunks, 4);

// ---- Enumerations -----------------------------------------------------------------------------
VKTG_CONST(uint, kMaterialDiffuse, 0);
VKTG_CONST(uint, kMaterialConductor, 1);   // rough conductor, GGX, scalar reflectance "albedo"
VKTG_CONST(uint, kMaterialDielectric, 2);  // rough dielectric, GGX, IOR
VKTG_CONST(uint, kMaterialCount, 3);

VKTG_CONST(uint, kGateSteady, 0);
VKTG_CONST(uint, kGateGaussian, 1);
VKTG_CONST(uint, kGateBox, 2);
VKTG_CONST(uint, kGateTruncatedGaussian, 3);
VKTG_CONST(uint, kGateBins, 4);

VKTG_CONST(uint, kCameraPerspective, 0);
VKTG_CONST(uint, kCameraPointSensor, 1);

VKTG_CONST(uint, kLightAreaTriangle, 0);
VKTG_CONST(uint, kLightPoint, 1);

VKTG_CONST(uint, kNeeStandard, 0);
VKTG_CONST(uint, kNeeEllipsoidal, 1);
VKTG_CONST(uint, kNeeMis, 2);           // both, weighted by the power heuristic

// Bits of PathState.ids.w
VKTG_CONST(uint, kPathFlagAfterTransmission, 1);
// The path reached its current hit over an edge pass's boundary segment: that hit was placed, not
// sampled, so its emission counts without MIS, and the path's own first ellipsoidal vertex
// (bits kPathEllipsoidShift.., stored + 1) replaces pathInfo.y: the vertex after the boundary
// segment is fixed, so connections that would have to move it start after it.
VKTG_CONST(uint, kPathFlagEdgeArrival, 2);
// ... and that hit's own emission belongs to another edge strategy (towards the lights): skip it.
VKTG_CONST(uint, kPathFlagNoArrivalEmission, 4);
VKTG_CONST(uint, kPathEllipsoidShift, 8);
VKTG_CONST(uint, kNoPixel, 0xffffffffu);  // an edge sample whose path reaches no pixel

// Indices into the Counters buffer (uint array).
VKTG_CONST(uint, kCounterRays0, 0);          // ray queue 0 size
VKTG_CONST(uint, kCounterRays1, 1);          // ray queue 1 size
VKTG_CONST(uint, kCounterShadow, 2);         // paths with shadow rays queued
VKTG_CONST(uint, kCounterExtensionRays, 3);  // statistics from here on
VKTG_CONST(uint, kCounterShadowRays, 4);
VKTG_CONST(uint, kCounterEndedByGate, 5);    // paths ended because their length passed the gate
VKTG_CONST(uint, kCounterEndedByRoulette, 6);
VKTG_CONST(uint, kCounterEndedByDepth, 7);
VKTG_CONST(uint, kCounterNonFinite, 8);      // NaN/Inf contributions dropped (must stay 0)
VKTG_CONST(uint, kCounterEllipsoidQueries, 9);
VKTG_CONST(uint, kCounterEllipsoidEmpty, 10);  // queries whose shell met no surface
VKTG_CONST(uint, kCounterEdgeSilhouettes, 11);  // edge samples whose direction made the edge a silhouette
VKTG_CONST(uint, kCounterEdgeConnected, 12);    // ... whose boundary segment also reached the camera
VKTG_CONST(uint, kCounterGradientOverflow, 13);  // adjoint scatters beyond the int64 range (the scale was too fine)
VKTG_CONST(uint, kCounterEdgeQueues, 14);  // 14..16: edge samples queued for each strategy (sample_edges)
VKTG_CONST(uint, kCounterCount, 17);

// Indices of VkDispatchIndirectCommand records in the dispatch-args buffer.
VKTG_CONST(uint, kArgsRays, 0);
VKTG_CONST(uint, kArgsShadow, 1);
VKTG_CONST(uint, kArgsCount, 2);

// ---- Descriptor bindings (set 0, one layout shared by every pass) ----------------------------
// Devices may allow as few as 32 storage buffers per stage (lavapipe), and the layout uses 31:
// bindings 25-28 therefore serve the derivative lanes of forward-mode passes and, under other
// names, the adjoint passes and the edge passes, which never run together with them.
VKTG_CONST(uint, kBindingFrame, 0);          // uniform FrameUniforms
VKTG_CONST(uint, kBindingTriangles, 1);      // GpuTriangle[], kMaxBufferChunks bindings: 1..4
VKTG_CONST(uint, kBindingBvhNodes, 5);       // GpuBvhNode[], chunks 5..8
VKTG_CONST(uint, kBindingTriangleVerts, 9);  // uvec4[] vertex indices + shape, BVH order
VKTG_CONST(uint, kBindingVertices, 10);      // vec4[] vertex positions
VKTG_CONST(uint, kBindingShapes, 11);        // GpuShape[]
VKTG_CONST(uint, kBindingMaterials, 12);     // GpuMaterial[]
VKTG_CONST(uint, kBindingLights, 13);        // GpuLight[] with CDF
VKTG_CONST(uint, kBindingPaths, 14);         // PathState[batch]
VKTG_CONST(uint, kBindingHits, 15);          // HitRecord[batch]
// uint[4 * batch]: two path-index queues by depth parity, then the queue of paths with shadow rays
// to trace, then per path the mask of its filled shadow-ray slots.
VKTG_CONST(uint, kBindingRayQueues, 16);
VKTG_CONST(uint, kBindingShadowQueue, 17);   // ShadowRay[slot * batch + path] (lib/path.glsl, shadowSlot)
VKTG_CONST(uint, kBindingCounters, 18);      // uint[kCounterCount]
VKTG_CONST(uint, kBindingDispatchArgs, 19);  // uint[3 * kArgsCount]
VKTG_CONST(uint, kBindingPathAccum, 20);     // float[(batch * layers + layer) * channels + channel], per-path sums
// Film: element e = (channel * layers + layer) * pixels + pixel is 4 floats at 4e: a shift K (the
// element's first sample), the Kahan-compensated sum of (x - K) and its compensation, and the sum
// of (x - K)^2. Shifted sums keep the variance exact when it is tiny against the mean (near-delta
// gates, antithetic pairs). resolve turns them into (mean, variance of the mean). Chunks 21..24.
VKTG_CONST(uint, kBindingFilm, 21);
VKTG_CONST(uint, kFilmFloatsPerElement, 4);
VKTG_CONST(uint, kPathsPerRound, 16384);  // accumulate: paths one invocation sums per dispatch
VKTG_CONST(uint, kBindingVertexVelocity, 25);  // vec4[lane * vertices + vertex]: dV/dθ of each lane
VKTG_CONST(uint, kBindingLanes, 26);           // GpuLane[lanes]: what each derivative lane differentiates
VKTG_CONST(uint, kBindingPathDerivs, 27);      // PathDerivative[path * lanes + lane]
VKTG_CONST(uint, kBindingShadowDerivs, 28);    // vec2[shadow ray * lanes + lane]: d value, d length
// Adjoint passes (THEORY.md §7: the gradient of a loss, no lanes):
VKTG_CONST(uint, kBindingAdjointImage, 25);    // float[layer * pixels + pixel]: d loss / d image
VKTG_CONST(uint, kBindingGradient, 26);        // int64[]: fixed-point gradient accumulators (FrameUniforms.gradientLayout)
VKTG_CONST(uint, kBindingTape, 27);            // TapeVertex[vertex * batch + path]
VKTG_CONST(uint, kBindingShadowAdjoint, 28);   // ShadowAdjoint[shadow slot]: what a connection's vertices are
// Edge passes (forward and adjoint): the boundary geometry of every path slot.
VKTG_CONST(uint, kBindingEdgeRecords, 27);     // EdgeRecord[slot]
VKTG_CONST(uint, kBindingEdgeFaces, 28);       // uvec4[edge]: as kUpdateBindingEdgeFaces
VKTG_CONST(uint, kBindingTestIn, 29);        // test kernels only
VKTG_CONST(uint, kBindingTestOut, 30);       // test kernels only
VKTG_CONST(uint, kBindingEdges, 31);        // GpuEdge[]: silhouette-capable edges with a CDF by length
VKTG_CONST(uint, kBindingCount, 32);  // storage-buffer bindings 0..31
// Uniform texel buffers (R32G32B32A32_UINT), in every layout: read-only views of buffers the
// storage bindings also hold. A CPU device fetches a lane's texel as one 16-byte load, where it
// loads a storage buffer's components one lane and one bounds check at a time. The scene's
// triangles and BVH nodes are read through them where kSpecSceneTexels is set, the path states and
// hits where kSpecWaveTexels is (shadow rays through them measured no faster), the 4-wide tree's
// nodes where kSpecWideBvh is (only through this view).
VKTG_CONST(uint, kFirstTexelBinding, 32);
VKTG_CONST(uint, kBindingTriangleTexels, 32);
VKTG_CONST(uint, kBindingBvhNodeTexels, 33);
VKTG_CONST(uint, kBindingPathTexels, 34);  // PathState[batch], read by intersect_closest and shade
VKTG_CONST(uint, kBindingHitTexels, 35);   // HitRecord[batch], read by shade
VKTG_CONST(uint, kBindingWideBvhTexels, 36);  // GpuWideBvhNode[] (kSpecWideBvh)
VKTG_CONST(uint, kTexelBindingCount, 5);

// Scene-update passes (move_vertices, update_triangles, refit_bvh, update_edges) use their own layout:
// bindings 0-13 as above (frame and scene), then these.
VKTG_CONST(uint, kUpdateBindingBasePositions, 14);  // vec4[vertex]: positions at θ = 0
VKTG_CONST(uint, kUpdateBindingVertexOps, 15);      // uvec2[vertex]: (first, count) in the op list
VKTG_CONST(uint, kUpdateBindingOpList, 16);         // uint[]: θ indices, per vertex in declaration order
VKTG_CONST(uint, kUpdateBindingParameterOps, 17);   // GpuParameterOp[θ index]
VKTG_CONST(uint, kUpdateBindingTheta, 18);          // float[θ index]
VKTG_CONST(uint, kUpdateBindingRefitOrder, 19);     // uint[]: internal BVH nodes, deepest level first
VKTG_CONST(uint, kUpdateBindingEdges, 20);          // GpuEdge[]
VKTG_CONST(uint, kUpdateBindingEdgeFaces, 21);      // uvec4[edge]: x, y the vertex opposite the edge in face 0, 1; z, w those faces' triangles, leaf order (~0: none)
VKTG_CONST(uint, kUpdateBindingWideBvhNodes, 22);  // GpuWideBvhNode[] (refit_wide_bvh)
VKTG_CONST(uint, kUpdateBindingSahPartials, 23);   // float[invocation]: bvh_sah_cost's partial sums
VKTG_CONST(uint, kUpdateBindingCount, 24);

// Shadow-ray slots of a path per bounce: per vertex a standard connection, an (antithetic) pair of
// ellipsoidal ones and the path-length-boundary ones (one per jump; the adjoint pass that runs the
// interior and path-length-boundary terms on the same paths fills both kinds). A boundary
// connection may share the mirror's slot: mirrors are for gaussian gates, which have no jumps.
// All of it for two vertices, since at a point sensor generate_camera_rays (the sensor) and the
// first hit queue theirs before the same trace. A slot's place is fixed, (vertex depth & 1) *
// kConnectionsPerVertex + kind, and trace_shadow_rays visits a path's slots in order, so a path's
// contributions add up in the same order on every run.
VKTG_CONST(uint, kConnectionsPerVertex, 4);
VKTG_CONST(uint, kConnectionStandard, 0);
VKTG_CONST(uint, kConnectionEllipsoidal, 1);  // and 2: the antithetic mirror
VKTG_CONST(uint, kConnectionBoundary, 2);     // and 3: the second jump
VKTG_CONST(uint, kShadowRaysPerPath, 8);
VKTG_CONST(uint, kNoJump, 0xffffffffu);  // ShadowRay.info.z of a connection that samples its length (not on a jump)
VKTG_CONST(uint, kNoTape, 0xffffffffu);  // ShadowRay.info.w of a connection from the camera (no tape vertex)

// ---- Specialisation constants (ids) and push constants of the passes ---------------------------
VKTG_CONST(uint, kSpecMaterialMask, 0);   // bit per kMaterial* present in the scene
VKTG_CONST(uint, kSpecNeeMode, 1);        // kNeeStandard / kNeeEllipsoidal / kNeeMis
VKTG_CONST(uint, kSpecGateType, 2);       // kGate*
VKTG_CONST(uint, kSpecCameraType, 3);     // kCamera*
VKTG_CONST(uint, kSpecLightMask, 4);      // bit kLightAreaTriangle / kLightPoint present
VKTG_CONST(uint, kSpecLanes, 5);          // derivative lanes K per path (derivative variants only)
VKTG_CONST(uint, kSpecTerm, 6);           // kTerm* (derivative variants only)
VKTG_CONST(uint, kSpecAntithetic, 7);     // 1: ellipsoidal connections in antithetic pairs s, 2 mu - s
VKTG_CONST(uint, kSpecAdjointTargets, 8); // adjoint variants: kAdjoint* bits, what the gradient is taken of
VKTG_CONST(uint, kSpecEllipsoidSelection, 9);  // kEllipsoidDescend / kEllipsoidEnumerate
VKTG_CONST(uint, kSpecCameraConnections, 10);   // 1: the shadow queue holds connect_camera_boundary's connections
VKTG_CONST(uint, kSpecSingleChunk, 11);  // 1: triangles, BVH nodes and film each fit their first chunk
VKTG_CONST(uint, kSpecSceneTexels, 12);  // 1: triangle and BVH node loads through the texel bindings
VKTG_CONST(uint, kSpecWaveTexels, 13);   // 1: path-state and hit loads through the texel bindings
VKTG_CONST(uint, kSpecWideBvh, 14);      // 1: closest- and any-hit traversal over the 4-wide BVH
VKTG_CONST(uint, kSpecMultiView, 15);    // 1: several views in one render (FrameUniforms.viewInfo, lib/view.glsl)
VKTG_CONST(uint, kSpecFilledSlotsOnly, 16);  // 1: trace_shadow_rays loops over a path's filled slots only (CPU devices)
VKTG_CONST(uint, kSpecEdgeStrategy, 17);     // sample_edges: the strategy whose queue it runs, kEdgeSortSamples, or kEdgeStrategyCount: all samples, every strategy
VKTG_CONST(uint, kSpecScatterAggregate, 18);  // 1: adjoint scatters sum a subgroup's adds to one accumulator first (GPUs)
VKTG_CONST(uint, kSpecStratifiedBoundary, 19);  // 1: edge and camera-connection samples stratified (rng.glsl)
VKTG_CONST(uint, kSpecCount, 20);

// sample_edges' strategies (its header): the camera's segment through the edge, a light's, a uniform direction.
VKTG_CONST(uint, kEdgeStrategyPrimary, 0);
VKTG_CONST(uint, kEdgeStrategyToLight, 1);
VKTG_CONST(uint, kEdgeStrategySecondary, 2);
VKTG_CONST(uint, kEdgeStrategyCount, 3);
VKTG_CONST(uint, kEdgeSortSamples, 4);  // sample_edges' first step: empty slots, and a queue per strategy

// How an ellipsoidal connection chooses its triangle (shaders/lib/ellipsoid.glsl).
VKTG_CONST(uint, kEllipsoidDescend, 0);    // stochastic BVH descent: cost logarithmic in triangles
VKTG_CONST(uint, kEllipsoidEnumerate, 1);  // every triangle the shell meets, by arc length

// What an adjoint render differentiates (kSpecAdjointTargets): only these get gradients computed.
VKTG_CONST(uint, kAdjointVertices, 1);    // positions of vertices of shapes with kShapeMoves
VKTG_CONST(uint, kAdjointMaterials, 2);   // albedo, roughness, ior
VKTG_CONST(uint, kAdjointEmission, 4);    // emitted radiance of shapes
VKTG_CONST(uint, kAdjointLights, 8);      // point-light positions and intensities
VKTG_CONST(uint, kAdjointGate, 16);       // the gate's centre
// With kAdjointVertices: the world axes some parameter moves vertices along. Only these components
// of a vertex's gradient are accumulated (a heightfield's heights need y alone).
VKTG_CONST(uint, kAdjointVertexX, 32);
VKTG_CONST(uint, kAdjointVertexY, 64);
VKTG_CONST(uint, kAdjointVertexZ, 128);
// Not a target: the interior term's paths also add their values to the film, as a render's do, so
// that later passes of a chained gradient can weight by an adjoint image that includes them.
VKTG_CONST(uint, kAdjointImage, 256);

VKTG_CONST(uint, kTermInterior, 0);       // d/dθ [W(L) f] along sampled paths
VKTG_CONST(uint, kTermPathLength, 1);     // paths on L = s at the gate's jumps, weighted ΔW(s) dL/dθ
VKTG_CONST(uint, kTermInteriorAndPathLength, 2);  // both from one set of paths (adjoint only)

// What a derivative lane differentiates (GpuLane.info.x).
VKTG_CONST(uint, kLaneGeometry, 0);       // vertex velocities (kBindingVertexVelocity) and/or a point light's velocity
VKTG_CONST(uint, kLaneAlbedo, 1);         // info.y: material
VKTG_CONST(uint, kLaneRoughness, 2);      // info.y: material
VKTG_CONST(uint, kLaneIor, 3);            // info.y: material
VKTG_CONST(uint, kLaneEmission, 4);       // info.y: shape
VKTG_CONST(uint, kLaneIntensity, 5);      // info.y: index in the lights array
VKTG_CONST(uint, kLaneGateCenter, 6);     // the whole gate shifts along L

struct PassPush {
  uvec4 args;  // x: first pixel-sample index of the batch, y: first sample index, z: depth, w: pass-specific
};

// ---- Scene -----------------------------------------------------------------------------------
// Triangle in BVH leaf order. p0.w holds the shape index, p1.w the original triangle index
// (both as uint bits), p2.w the triangle's area.
struct GpuTriangle {
  vec4 p0;
  vec4 p1;
  vec4 p2;
};

// Two-wide BVH node holding both children's boxes (one fetch tests both). A node with
// count > 0 is a leaf covering triangles [first, first + count); its boxes are unused. An
// interior node's subtrees cover contiguous ranges of leaf order; its `first` is where the right
// subtree's range begins (an ellipsoidal connection's density walks to one triangle with it).
struct GpuBvhNode {
  vec4 leftMinLeftIndex;    // xyz: left child box min, w: left child node index (uint bits)
  vec4 leftMaxRightIndex;   // xyz: left child box max, w: right child node index (uint bits)
  vec4 rightMinCount;       // xyz: right child box min, w: leaf triangle count (uint bits)
  vec4 rightMaxFirst;       // xyz: right child box max, w: first triangle of the leaf / right subtree (uint bits)
};

// A node of the 4-wide BVH (the binary tree collapsed, kSpecWideBvh), children in structure-of-
// arrays order so one lane's four slab tests are vec4 operations. child[k]: an inner node's index,
// or kWideBvhLeaf | first << kWideBvhFirstShift | count for a leaf of `count` triangles from
// `first` (leaf order), or kWideBvhEmpty for an unused slot, whose box is empty (lo > hi).
// source[k]: where the binary tree keeps that child's box: 2 * node + 0 (left) or 1 (right).
struct GpuWideBvhNode {
  vec4 loX;
  vec4 loY;
  vec4 loZ;
  vec4 hiX;
  vec4 hiY;
  vec4 hiZ;
  uvec4 child;
  uvec4 source;
};
VKTG_CONST(uint, kWideBvhLeaf, 0x80000000u);
VKTG_CONST(uint, kWideBvhFirstShift, 6);
VKTG_CONST(uint, kWideBvhMaxLeafCount, 63);     // also the mask of the count
VKTG_CONST(uint, kWideBvhMaxFirst, 0x01ffffffu);
VKTG_CONST(uint, kWideBvhEmpty, 0xffffffffu);

VKTG_CONST(uint, kShapeMoves, 1);  // GpuShape.flags: some optimised parameter moves its vertices

struct GpuShape {
  uint material;
  float emission;    // emitted radiance of the front face (W sr^-1 m^-2); 0 = not an emitter
  uint flags;        // kShape*
  uint unused;
};

// ParameterKind values move_vertices distinguishes (include/vktg/parameters.h).
VKTG_CONST(uint, kParameterTranslate, 0);
VKTG_CONST(uint, kParameterRotate, 1);
VKTG_CONST(uint, kParameterDisplace, 2);

// A Translate, Rotate or Displace parameter as move_vertices applies it (ParameterModel).
struct GpuParameterOp {
  vec4 axisKind;     // xyz: axis (Displace: the displacement per unit θ); w: ParameterKind (uint bits)
  vec4 center;       // xyz: a point on a rotation's axis
};

struct GpuMaterial {
  uint type;         // kMaterial*
  float albedo;      // diffuse reflectance / conductor specular reflectance / dielectric tint
  float roughness;   // GGX alpha
  float ior;         // dielectric index of refraction (inside / outside)
};

// One entry of the light-selection CDF: an emissive triangle or a point light.
struct GpuLight {
  vec4 positionIntensity;  // point light: xyz position, w intensity (W/sr); area: unused
  uint type;               // kLight*
  uint triangle;           // area light: index into the BVH-ordered triangle array
  float cdf;               // inclusive CDF of selection probabilities, a multiple of 2^-24 (the
                           // shaders' random numbers' step), so that selection gives exactly `pmf`
  float pmf;               // selection probability: this light's step of the CDF
};

// An edge that can be a silhouette: a mesh boundary, or the crease between two faces that are not
// coplanar (a flat crease never is). Positions are the scene's at θ0; the vertex indices find the
// velocities of each lane (kBindingVertexVelocity).
struct GpuEdge {
  vec4 p0;       // xyz: first end, w: its vertex index (uint bits)
  vec4 p1;       // xyz: second end, w: its vertex index (uint bits)
  vec4 inward0;  // xyz: unit direction in face 0, perpendicular to the edge, into the face; w: uint bits, the
                 // end of the edge's interval [previous edge's end, end) of 32-bit selection numbers (the last
                 // edge's 2^32 is stored as 0)
  vec4 inward1;  // xyz: the same in face 1 (zero for a boundary edge); w: selection probability, the interval's
                 // width / 2^32
};

// ---- Per-frame constants -----------------------------------------------------------------------
struct FrameUniforms {
  vec4 cameraPosition;    // xyz; w: unused
  vec4 cameraForward;     // perspective: unit view direction; point sensor: unit normal; w: the view's
                          // optical path outside the scene (lib/view.glsl, viewPathOffset)
  vec4 cameraRight;       // scaled by tan(fov_y/2) * aspect
  vec4 cameraUp;          // scaled by tan(fov_y/2)
  uvec4 image;            // x: width, y: height, z: spp, w: seed
  uvec4 sceneCounts;      // x: triangles, y: lights, z: shapes, w: camera type
  vec4 gate;              // gaussian/tgauss: (mu, sigma, a, b); box: (-, -, a, b); bins: (start, width, -, -)
  vec4 gateSupport;       // x: support min, y: where paths end (support max, or inf without the cutoff),
                          // z: support max (gate sampling), w: gaussian normaliser
  uvec4 gateInfo;         // x: gate type, y: bin count, z: nee mode, w: max depth
  uvec4 pathInfo;         // x: roulette depth, y: first vertex with an ellipsoidal connection, z: channels, w: batch size
  vec4 sceneInfo;         // x: ray epsilon (scene-scale relative), y: scene diagonal, z: total light power, w: vertex count (uint bits)
  uvec4 chunkShift;       // log2 of elements per chunk: x triangles, y BVH nodes, z film floats, w unused
  uvec4 edgeInfo;         // x: silhouette-capable edges (kBindingEdges), y: edge samples of the render, z, w unused
  // Adjoint passes: where each scene quantity's accumulators start in kBindingGradient (int64 slots):
  // slot 0 the gate centre, then x: materials (albedo, roughness, ior each), y: shape emission,
  // z: point lights (intensity, position xyz each), w: vertices (each the components some parameter
  // moves vertices along, in x, y, z order: lib/adjoint.glsl, scatterVertex).
  uvec4 gradientLayout;
  uvec4 adjointInfo;      // x: index of the first point light in the lights array, y-w unused
  vec4 adjointScale;      // x: accumulators hold round(value * x) (a power of two), y: the samples a pixel's
                          // mean averages (adjointOf), z-w unused
  // A render of several views (kSpecMultiView; lib/view.glsl): x views, y image rows of one view
  // (image.y counts the rows of all of them, stacked), z vec4s per view record in the frame block's
  // view array, w lights[] index of the first point light. One view: (1, image.y, 0, -).
  uvec4 viewInfo;
};

struct GpuLane {
  uvec4 info;           // x: kLane*, y: target index, z: 1 if the lane moves a point light, w: unused
  vec4 lightVelocity;   // xyz: velocity of the point light info.y (geometry lanes)
};

// ---- Wavefront state ---------------------------------------------------------------------------
struct PathState {
  vec4 position;    // xyz: current vertex (un-offset, exact); w: optical path length so far
  vec4 direction;   // xyz: direction of the next segment; w: Kahan compensation of the length
  vec4 normal;      // xyz: geometric normal at the vertex; w: throughput (f cos / pdf products)
  vec4 misc;        // x: solid-angle pdf of the last BSDF sample (MIS); y: IOR of the medium the
                    // next segment travels in; z: the path's view (uint bits, lib/view.glsl); w: unused
  uvec4 ids;        // x: pixel, y: sample index, z: depth (vertices after x0), w: flags
  vec4 previous;    // xyz: the vertex before the current one; w: triangle of the current vertex
                    // (uint bits; ~0 at the camera or sensor). Derivative passes read them.
};

// Derivative state of one path for one lane (forward mode, material form).
struct PathDerivative {
  vec4 positionThroughput;  // xyz: d(current vertex), w: d(throughput without its pending factor)
  vec4 previousLength;      // xyz: d(previous vertex), w: d(path length)
};

struct HitRecord {
  vec4 tuvTriangle;  // x: t (< 0 for a miss), y, z: barycentrics u, v, w: triangle (uint bits)
};

// A deferred contribution tested for visibility: one segment (standard NEE) or two (ellipsoidal).
struct ShadowRay {
  vec4 p0Value;      // xyz: first point, w: contribution if visible
  vec4 p1Length;     // xyz: second point, w: total optical path length of the path
  vec4 p2;           // xyz: third point (two-segment rays only)
  uvec4 info;        // x: path index, y: segment count (1 or 2; 0: empty slot), z: gate jump (path-length
                     // boundary), w: depth of the vertex the connection starts from (kNoTape: the camera)
};

// Adjoint passes: the material points of a connection beyond its first vertex, so its gradient can
// be scattered onto the vertices they lie on.
struct ShadowAdjoint {
  uvec4 middle;      // x: triangle of the ellipsoidal vertex, or of the emitter point a one-segment camera
                     // connection reaches (~0: none); y, z: barycentrics (float bits); w: 1 if it is a first
                     // hit kept on its camera ray
  uvec4 light;       // x: lights[] index of the light sample (~0: none); y, z: barycentrics of an area-light
                     // point (float bits); w: unused
};

// Adjoint passes: one vertex of a path, written as the wavefront reaches it, read back by
// backprop_paths, which walks each path backwards once every contribution is known (the tape).
struct TapeVertex {
  vec4 hit;          // x: triangle (uint bits; ~0 at the camera), y, z: barycentrics, w: IOR of the medium
                     // the segment arriving here ran in
  vec4 adjoint;      // x: sum over contributions closed at this vertex (emission, its connections) of
                     // d loss/d I * W(L) * value; y: the same with W'(L) (the path-length adjoint);
                     // z (entry 0 only): surface vertices on the tape (uint bits); w: unused
};

// Edge passes: the boundary segment behind a path slot. The slot's derivative is its light-side value
// times a factor linear in velocities:
//   factor = sY (v_y . n_p) + sA (v_a . n_p) + sB (v_b . n_p),
// v_y the edge's velocity at y, v_a and v_b those of the segment's ends (lib/edge.glsl).
struct EdgeRecord {
  vec4 normalScale;  // xyz: n_p; w: sY (0: the slot holds no boundary sample)
  vec4 ends;         // x: position of y along the edge, y: sA, z: sB, w: edge index (uint bits)
  uvec4 endA;        // x: triangle of x_a (~0: the camera or sensor, which do not move), y, z: barycentrics
                     // (float bits), w: 1 if x_a is a first hit kept on its camera ray
  uvec4 endB;        // x: triangle of x_b (~0: none), y, z: barycentrics (float bits), w: lights[] index of a
                     // point light at x_b (~0: none)
};

#ifdef __cplusplus
}  // namespace vktg::gpu
#endif
#endif
