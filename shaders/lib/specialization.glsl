// Specialisation constants (ids in vktg/gpu/shared.h): the planner sets them per scene so the
// driver compiles only the code that scene needs (materials, lights, gate, estimator, camera).
// On a CPU device this is what a branch cannot do: lavapipe runs both sides of every branch with
// the lanes masked, so code that is compiled in costs its time even where no lane takes it.
#ifndef VKTG_SPECIALIZATION_GLSL
#define VKTG_SPECIALIZATION_GLSL
layout(constant_id = 0) const uint kSpecMaterialMaskValue = 7u;
layout(constant_id = 1) const uint kSpecNeeModeValue = 0u;
layout(constant_id = 2) const uint kSpecGateTypeValue = 0u;
layout(constant_id = 3) const uint kSpecCameraTypeValue = 0u;
layout(constant_id = 4) const uint kSpecLightMaskValue = 3u;
layout(constant_id = 5) const uint kSpecLanesValue = 1u;  // derivative lanes (derivative variants)
layout(constant_id = 6) const uint kSpecTermValue = 0u;   // kTerm*
layout(constant_id = 7) const uint kSpecAntitheticValue = 0u;
layout(constant_id = 8) const uint kSpecAdjointTargetsValue = 0u;  // kAdjoint* bits (adjoint variants)
layout(constant_id = 9) const uint kSpecEllipsoidSelectionValue = 0u;  // kEllipsoidDescend / kEllipsoidEnumerate
layout(constant_id = 10) const uint kSpecCameraConnectionsValue = 0u;  // 1: connections from the camera
layout(constant_id = 11) const uint kSpecSingleChunkValue = 0u;  // 1: chunked buffers hold one chunk each
layout(constant_id = 12) const uint kSpecSceneTexelsValue = 0u;  // 1: scene loads through texel buffers
layout(constant_id = 13) const uint kSpecWaveTexelsValue = 0u;   // 1: path-state and hit loads through texels
layout(constant_id = 14) const uint kSpecWideBvhValue = 0u;      // 1: traversal over the 4-wide BVH
layout(constant_id = 15) const uint kSpecMultiViewValue = 0u;    // 1: several views per render (lib/view.glsl)
layout(constant_id = 16) const uint kSpecFilledSlotsOnlyValue = 0u;  // 1: trace_shadow_rays skips empty slots
layout(constant_id = 17) const uint kSpecEdgeStrategyValue = 3u;     // sample_edges: one strategy, or 3: all
layout(constant_id = 18) const uint kSpecScatterAggregateValue = 0u;  // 1: lib/adjoint.glsl sums shared adds per subgroup
layout(constant_id = 19) const uint kSpecStratifiedBoundaryValue = 1u;  // 1: stratified edge, camera samples

bool sceneHasLightType(uint type) { return (kSpecLightMaskValue & (1u << type)) != 0u; }
bool sceneHasMaterial(uint type) { return (kSpecMaterialMaskValue & (1u << type)) != 0u; }
#endif
