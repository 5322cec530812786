#include "render/planner.h"

#include <cmath>
#include <cstdarg>
#include <cstdio>

#include "vktg/error.h"

namespace vktg {

std::string formatReason(const char* fmt, ...) {
  char text[512];
  va_list args;
  va_start(args, fmt);
  std::vsnprintf(text, sizeof text, fmt, args);
  va_end(args);
  return text;
}

const char* neeModeName(NeeMode mode) {
  switch (mode) {
    case NeeMode::Auto: return "auto";
    case NeeMode::Standard: return "standard";
    case NeeMode::Ellipsoidal: return "ellipsoidal";
    case NeeMode::Mis: return "mis";
  }
  return "?";
}

const char* ellipsoidSelectionName(EllipsoidSelection selection) {
  switch (selection) {
    case EllipsoidSelection::Auto: return "auto";
    case EllipsoidSelection::Descend: return "descend";
    case EllipsoidSelection::Enumerate: return "enumerate";
  }
  return "?";
}

RenderPlan planRender(const RenderSetup& setup, const PreparedScene& prepared, NeeMode requested,
                      EllipsoidSelection selection, const std::vector<std::string>& neeNotes) {
  RenderPlan plan;
  const Gate& gate = setup.gate;
  plan.layers = gate.layers();
  plan.gateWidth = gate.width();
  plan.pathSpread = std::max(double(glm::length(prepared.boundsMax - prepared.boundsMin)), 1e-9);
  plan.firstEllipsoidVertex = firstEllipsoidVertex(setup.camera.type);
  bool fromScene = requested == NeeMode::Auto;
  NeeMode mode = fromScene ? setup.settings.nee : requested;
  // Name where the choice came from: the scene file's render.nee or the --nee option.
  std::string file = fromScene ? setup.source : "";
  std::string field = fromScene ? "render.nee" : "--nee";
  if ((mode == NeeMode::Ellipsoidal || mode == NeeMode::Mis) && gate.type == GateType::Steady)
    fail(file, field, std::string(neeModeName(mode)) +
                          " NEE needs a gate of finite extent (it samples path lengths from the gate); the gate is steady");

  if (mode == NeeMode::Auto) {
    if (gate.type == GateType::Steady) {
      mode = NeeMode::Standard;
      plan.reasons.push_back("standard NEE: the gate is steady, every path length counts");
    } else {
      double ratio = plan.gateWidth / plan.pathSpread;
      mode = ratio < kEllipsoidalGateFraction ? NeeMode::Ellipsoidal : NeeMode::Standard;
      plan.reasons.push_back(formatReason(mode == NeeMode::Ellipsoidal
                                              ? "ellipsoidal NEE: gate width %.4g m is %.2g of the scene's path-length spread %.4g m (< 0.05); standard NEE would miss the gate with most samples"
                                              : "standard NEE: gate width %.4g m is %.2g of the scene's path-length spread %.4g m (>= 0.05); enough standard samples land in the gate",
                                          plan.gateWidth, ratio, plan.pathSpread));
    }
    plan.reasons.insert(plan.reasons.end(), neeNotes.begin(), neeNotes.end());
  } else if (!fromScene && !neeNotes.empty()) {
    plan.reasons.insert(plan.reasons.end(), neeNotes.begin(), neeNotes.end());
  } else {
    plan.reasons.push_back(std::string(neeModeName(mode)) + " NEE: requested");
  }
  plan.nee = mode;
  if (mode == NeeMode::Mis)
    plan.reasons.push_back("mis: paths long enough for an ellipsoidal connection get both it and standard NEE, weighted by the power heuristic");
  if (mode == NeeMode::Ellipsoidal || mode == NeeMode::Mis) {
    const size_t triangles = prepared.triangles.size();
    if (selection == EllipsoidSelection::Auto) {
      selection = EllipsoidSelection::Descend;
      plan.reasons.push_back(formatReason("ellipsoidal connections choose their triangle by a stochastic BVH descent: cost grows with the tree's depth, not with the %zu triangles", triangles));
    } else {
      plan.reasons.push_back(std::string("ellipsoidal connections choose their triangle by ") +
                             (selection == EllipsoidSelection::Descend ? "a stochastic BVH descent" : "enumerating every triangle the shell meets") +
                             ": requested");
    }
    plan.ellipsoidSelection = selection;
  }
  if (mode == NeeMode::Ellipsoidal || mode == NeeMode::Mis)
    plan.reasons.push_back(plan.firstEllipsoidVertex == 0
                               ? "point sensor: ellipsoidal connections start at the sensor; direct light uses standard NEE"
                               : "pinhole camera: paths of 1-2 segments use standard NEE and emitter hits, longer ones ellipsoidal connections");
  if (gate.type != GateType::Steady)
    plan.reasons.push_back(formatReason("paths end once their length passes %.4g m (the gate's support); Russian roulette only after %.4g m",
                                        gate.supportMax(), gate.supportMin()));
  else
    plan.reasons.push_back(formatReason("steady gate: paths end by Russian roulette from depth %u or at max depth %u",
                                        setup.settings.rouletteDepth, setup.settings.maxDepth));
  std::string materials;
  const char* names[] = {"diffuse", "conductor", "dielectric"};
  for (uint32_t t = 0; t < 3; ++t)
    if (prepared.materialMask & (1u << t)) materials += std::string(materials.empty() ? "" : ", ") + names[t];
  plan.reasons.push_back("material code compiled in: " + materials);
  if (plan.layers > 1) plan.reasons.push_back(formatReason("transient stack: %u bins share every path", plan.layers));
  return plan;
}

std::string explainPlan(const RenderPlan& plan) {
  std::string out;
  for (const std::string& r : plan.reasons) out += "  - " + r + "\n";
  return out;
}

}  // namespace vktg
