// Experiment files (docs/optimize.md): strict parsing into vktg::Experiment. Like the scene parser,
// every error names the file, the JSON path of the field and the problem. Scenes may declare 10^6
// parameters (a heightfield's heights), so selecting and validating them is O(K log K): names are
// looked up in a map built once, never by a scan per name.
#include "opt/experiment.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <unordered_map>

#include "opt/experiment_capture.h"
#include "plan/terms.h"
#include "scene/mitsuba_xml.h"
#include "scene/mitsuba_xml_document.h"
#include "scene/scene_values.h"
#include "scene/scan.h"
#include "scene/scene_view.h"
#include "vktg/error.h"

namespace vktg {
namespace {

namespace fs = std::filesystem;

constexpr uint32_t kExperimentVersion = 1;
constexpr uint32_t kMaxSpp = 1u << 30;
constexpr uint32_t kMaxDepth = 1024;
// Each chained interior pass is a render and a round trip to the host for its adjoint image.
constexpr uint32_t kMaxInteriorPasses = 64;
constexpr uint32_t kMaxUint32 = std::numeric_limits<uint32_t>::max();
constexpr uint32_t kSynthesizeSeedBase = 0x5eed;
// Targets after scans are expanded: each is a log column and a render view.
constexpr size_t kMaxTargets = 1u << 16;
constexpr size_t kUnselected = std::numeric_limits<size_t>::max();

std::string inQuotes(const std::string& text) { return "\"" + text + "\""; }

std::string describeRange(const ParameterRange& r) {
  const bool lowOpen = r.lowOpen || std::isinf(r.low), highOpen = r.highOpen || std::isinf(r.high);
  return std::string(lowOpen ? "(" : "[") + formatNumber(r.low) + ", " + formatNumber(r.high) + (highOpen ? ")" : "]");
}

// The values both ranges allow.
ParameterRange intersect(const ParameterRange& a, const ParameterRange& b) {
  ParameterRange r = a;
  if (b.low > r.low || (b.low == r.low && b.lowOpen)) {
    r.low = b.low;
    r.lowOpen = b.lowOpen;
  }
  if (b.high < r.high || (b.high == r.high && b.highOpen)) {
    r.high = b.high;
    r.highOpen = b.highOpen;
  }
  return r;
}

bool isEmpty(const ParameterRange& r) { return r.low > r.high || (r.low == r.high && (r.lowOpen || r.highOpen)); }

// A value at `path` that the file does not contain (a defaulted field), for errors about defaults.
JsonValue absentField(const JsonObject& object, std::string_view key) {
  return JsonValue{&object.self().json(), object.self().file, object.pathOf(key)};
}

class ExperimentParser {
 public:
  ExperimentParser(std::string file, fs::path baseDir, SceneDefines defines)
      : m_file(std::move(file)), m_baseDir(std::move(baseDir)), m_defines(std::move(defines)) {}

  Experiment parse(const Json& json) {
    m_x.source = m_file;
    const JsonObject root(JsonValue{&json, m_file, ""},
                          {"version", "description", "scene", "parameters", "targets", "loss", "optimizer",
                           "regularizers", "preconditioner", "render", "stop", "checkpoint_every", "images_every",
                           "seed"});
    const JsonValue version = root.field("version");
    const uint32_t v = version.uinteger(0, kMaxUint32);
    if (v != kExperimentVersion)
      version.fail("unsupported version " + std::to_string(v) + " (this vktg reads version " +
                   std::to_string(kExperimentVersion) + ")");
    if (root.has("description")) root.field("description").string();
    loadSceneField(root.field("scene"));
    // Targets before parameters: a gate_center parameter's valid range depends on every target's gate.
    parseTargets(root.field("targets"));
    parseParameters(root.field("parameters"));
    if (root.has("loss")) parseLoss(root.field("loss"));
    if (root.has("optimizer")) parseOptimizer(root.field("optimizer"));
    checkGroups();
    if (root.has("regularizers")) {
      const JsonValue regularizers = root.field("regularizers");
      for (size_t i = 0; i < regularizers.array().size(); ++i) parseRegularizer(regularizers.element(i));
    }
    if (root.has("preconditioner")) parsePreconditioner(root.field("preconditioner"));
    if (root.has("render")) parseRender(root.field("render"));
    if (root.has("stop")) parseStop(root.field("stop"));
    m_x.checkpointEvery = root.uinteger("checkpoint_every", m_x.checkpointEvery, 1, kMaxUint32);
    m_x.imagesEvery = root.uinteger("images_every", m_x.imagesEvery, 1, kMaxUint32);
    m_x.seed = root.uinteger("seed", m_x.seed, 0, kMaxUint32);
    checkTruthForSynthesis();
    return std::move(m_x);
  }

 private:
  // "scene.json", or {"file": "scene.xml", "defines": {"name": "value", ...}, "parameters": [...]}
  // for a Mitsuba XML scene's $name values (numbers and booleans are written as JSON writes them)
  // and the parameters of a scene format that declares none (XML, glTF), in the JSON scene's form.
  void loadSceneField(const JsonValue& field) {
    JsonValue fileField = field;
    std::optional<JsonValue> parameters;
    if (field.json().is_object()) {
      const JsonObject o(field, {"file", "defines", "parameters"});
      fileField = o.field("file");
      if (o.has("parameters")) parameters = o.field("parameters");
      if (o.has("defines")) {
        const JsonValue defines = o.field("defines");
        if (!defines.json().is_object()) defines.fail("wrong type: expected an object mapping parameter names to values");
        for (const auto& item : defines.json().items()) {
          const JsonValue entry{&item.value(), m_file, defines.path + "." + item.key()};
          if (!isValidDefineName(item.key())) entry.fail("a parameter name uses only letters, digits and '_'");
          if (entry.json().is_string()) m_x.sceneDefines[item.key()] = entry.json().get<std::string>();
          else if (entry.json().is_number() || entry.json().is_boolean()) m_x.sceneDefines[item.key()] = entry.json().dump();
          else entry.fail("wrong type: expected a string, a number or a boolean");
        }
      }
    }
    for (const auto& [name, value] : m_defines) m_x.sceneDefines[name] = value;
    const std::string path = fileField.string();
    if (path.empty()) fileField.fail("empty path: name the scene file (relative to this file's folder)");
    m_x.scenePath = m_baseDir / path;
    try {
      if (isMitsubaXmlPath(m_x.scenePath)) {
        MitsubaScene loaded = loadMitsubaXml(m_x.scenePath, m_x.sceneDefines);
        m_x.scene = std::move(loaded.scene);
        m_sceneCapture = std::move(loaded.capture);
      } else {
        m_x.scene = loadScene(m_x.scenePath, m_x.sceneDefines);
      }
    } catch (const Error& e) {
      fileField.fail(e.what());
    }
    if (parameters) {
      if (lowerExtension(m_x.scenePath) == ".json")
        parameters->fail("a JSON scene declares its parameters in its own file (\"parameters\" there)");
      m_x.scene = withParameters(std::move(m_x.scene), *parameters);
    }
    const Scene& scene = m_x.scene;
    m_parameterIndex.reserve(scene.parameters.size());
    for (size_t k = 0; k < scene.parameters.size(); ++k) m_parameterIndex.emplace(scene.parameters[k].name, uint32_t(k));
    for (size_t s = 0; s < scene.shapes.size(); ++s) m_shapeIndex.emplace(scene.shapes[s].name, uint32_t(s));
  }

  // ---- targets ----

  void parseTargets(const JsonValue& value) {
    const Json& array = value.array();
    if (array.empty()) value.fail("no targets: give at least one (view, gate, image)");
    std::set<std::string> names;
    for (size_t i = 0; i < array.size(); ++i) parseTarget(value.element(i), i, names);
    if (m_x.targets.size() > kMaxTargets)
      value.fail(std::to_string(m_x.targets.size()) + " targets (scan points included); at most " +
                 std::to_string(kMaxTargets));
  }

  // One target, or one per point of a "scan" (named <name>_<column>_<row> for a grid, <name>_<k>
  // for a list of views; synthesised ones with consecutive seeds), or of a "capture" file.
  void parseTarget(const JsonValue& value, size_t entry, std::set<std::string>& names) {
    const JsonObject o(value, {"name", "view", "scan", "capture", "lights", "gate", "image", "weight"});
    Target target;
    target.entry = entry;
    target.name = o.string("name", "target_" + std::to_string(entry));
    target.entryName = target.name;
    const JsonValue nameWhere = o.has("name") ? o.field("name") : value;
    if (!isValidParameterName(target.name))
      nameWhere.fail("invalid target name " + inQuotes(target.name) +
                     " (use letters, digits, '_', '-' and '.': it names files and log columns)");
    // A scan's name names its log column and initial image, as a single target's does.
    if ((o.has("scan") || o.has("capture")) && !names.insert(target.name).second)
      nameWhere.fail("duplicate target name " + inQuotes(target.name));
    if (o.has("view") && o.has("scan")) o.field("scan").fail("a target takes a view or a scan, not both");
    if (o.has("lights") && !o.has("capture")) o.field("lights").fail("only with \"capture\": the lights at a capture's laser points");
    target.weight = o.number("weight", target.weight);
    if (o.has("weight")) requireAbove(o.field("weight"), target.weight, 0.0);
    if (o.has("capture")) {
      for (const char* other : {"view", "scan", "gate", "image"})
        if (o.has(other))
          o.field(other).fail("not with \"capture\": a capture file gives the target its views, its bins and its image");
      parseCapture(o, target, nameWhere, names);
      return;
    }
    if (o.has("view")) target.view = parseSceneView(o.field("view"), m_x.scene);
    target.gate = o.has("gate") ? parseGateValue(o.field("gate")) : m_x.scene.gate;
    parseImage(o.field("image"), m_x.targets.size(), target);
    // A Mitsuba XML capture (nlos_capture_meter) is the scene's own scan: a target without a view
    // or a scan measures it, as `vktg render` of the file renders it.
    if (!o.has("scan") && !o.has("view") && m_sceneCapture) {
      if (!names.insert(target.name).second) nameWhere.fail("duplicate target name " + inQuotes(target.name));
      addScanTargets(target, m_sceneCapture->views, m_sceneCapture->columns, m_sceneCapture->rows, m_sceneCapture->grid,
                     nameWhere, names);
      return;
    }
    if (!o.has("scan")) {
      addTarget(std::move(target), nameWhere, names);
      return;
    }
    const JsonValue scanField = o.field("scan");
    const std::string path = scanField.string();
    if (path.empty()) scanField.fail("empty path: name a scan file (relative to this file's folder)");
    const Scan scan = loadScan(m_baseDir / path, m_x.scene);
    addScanTargets(target, scan.views, scan.columns, scan.rows, scan.grid, nameWhere, names);
  }

  // A scan's points as targets: `target` with each view, in scan order.
  void addScanTargets(const Target& target, const std::vector<SceneView>& views, uint32_t columns, uint32_t rows, bool grid,
                      const JsonValue& nameWhere, std::set<std::string>& names) {
    for (size_t k = 0; k < views.size(); ++k) {
      Target point = target;
      const uint32_t column = uint32_t(k % columns), row = uint32_t(k / columns);
      point.name += grid ? "_" + std::to_string(column) + "_" + std::to_string(row) : "_" + std::to_string(k);
      point.view = views[k];
      point.scanView = uint32_t(k);
      point.scanViews = uint32_t(views.size());
      point.scanColumns = columns;
      point.scanRows = rows;
      if (point.synthesize) point.synthesizeSeed = target.synthesizeSeed + uint32_t(k);
      addTarget(std::move(point), nameWhere, names);
    }
  }

  // {"capture": FILE, "lights": [NAMES]}: a scan whose views, bins and image a capture file holds
  // (experiment_capture.cpp).
  void parseCapture(const JsonObject& o, Target target, const JsonValue& nameWhere, std::set<std::string>& names) {
    const JsonValue field = o.field("capture");
    const std::string path = field.string();
    if (path.empty()) field.fail("empty path: name an HDF5 capture file (relative to this file's folder)");
    if (m_x.scene.camera.type != CameraType::PointSensor)
      field.fail("a capture's transients are measured by a point sensor at each wall point, but the scene's camera is a pinhole");
    std::vector<uint32_t> lights;
    const JsonValue lightsField = o.field("lights");
    if (lightsField.array().empty()) lightsField.fail("empty list: name the scene's point lights that sit at the laser points");
    for (size_t k = 0; k < lightsField.array().size(); ++k) {
      const JsonValue name = lightsField.element(k);
      const uint32_t light = pointLightIndex(name, m_x.scene, name.string());
      if (std::find(lights.begin(), lights.end(), light) != lights.end()) name.fail("light " + inQuotes(name.string()) + " listed twice");
      lights.push_back(light);
    }
    target.image = m_baseDir / path;
    target.capture = true;
    const CaptureTargets expanded = captureTargets(target.image, lights, field);
    target.gate = expanded.gate;
    addScanTargets(target, expanded.views, expanded.columns, expanded.rows, expanded.grid, nameWhere, names);
  }

  void addTarget(Target target, const JsonValue& nameWhere, std::set<std::string>& names) {
    if (!names.insert(target.name).second) nameWhere.fail("duplicate target name " + inQuotes(target.name));
    m_x.targets.push_back(std::move(target));
  }

  void parseImage(const JsonValue& value, size_t index, Target& target) {
    if (value.json().is_string()) {
      const std::string path = value.string();
      if (path.empty()) value.fail("empty path: name an EXR file (relative to this file's folder)");
      target.image = m_baseDir / path;
      std::error_code error;
      if (!fs::exists(target.image, error)) value.fail(target.image.string() + ": file not found");
      if (!fs::is_regular_file(target.image, error)) value.fail(target.image.string() + ": cannot read: not a regular file");
      if (!std::ifstream(target.image, std::ios::binary))
        value.fail(target.image.string() + ": cannot read file (permission denied or I/O error)");
      return;
    }
    if (!value.json().is_object())
      value.fail("wrong type: expected the path of an EXR file or {\"synthesize\": {\"spp\": N, \"seed\": S}}");
    const JsonObject o(value, {"synthesize"});
    const JsonObject synthesize(o.field("synthesize"), {"spp", "seed"});
    target.synthesize = true;
    target.synthesizeSpp = synthesize.uinteger("spp", target.synthesizeSpp, 1, kMaxSpp);
    target.synthesizeSeed = synthesize.uinteger("seed", kSynthesizeSeedBase + uint32_t(index), 0, kMaxUint32);
  }

  // ---- parameters ----

  void parseParameters(const JsonValue& value) {
    const Json& array = value.array();
    if (array.empty()) value.fail("no parameters: name at least one scene parameter to optimise");
    m_selectedBy.assign(m_x.scene.parameters.size(), kUnselected);
    for (size_t i = 0; i < array.size(); ++i) parseParameterEntry(value.element(i), i);
  }

  void parseParameterEntry(const JsonValue& value, size_t entry) {
    const JsonObject o(value, {"name", "initial", "truth", "group", "range"});
    const JsonValue nameField = o.field("name");
    const std::vector<uint32_t> matches = matchParameters(nameField);
    const size_t count = matches.size();
    const std::vector<double> initial = valuesPerMatch(o, "initial", count).value_or(std::vector<double>(count, 0.0));
    const std::optional<std::vector<double>> truth = valuesPerMatch(o, "truth", count);
    std::string group = "default";
    if (o.has("group")) {
      group = o.field("group").string();
      if (group.empty()) o.field("group").fail("empty group name");
      m_groupFields.emplace_back(group, o.pathOf("group"));
    }
    std::optional<ParameterRange> narrowed;
    if (o.has("range")) {
      const JsonValue range = o.field("range");
      const std::vector<double> bounds = range.numbers(2);
      if (!(bounds[0] < bounds[1])) range.fail("empty range: the low end must be below the high end");
      narrowed = ParameterRange{bounds[0], bounds[1], false, false};
    }

    for (size_t m = 0; m < count; ++m) {
      const uint32_t k = matches[m];
      const Parameter& p = m_x.scene.parameters[k];
      if (m_selectedBy[k] != kUnselected)
        nameField.fail("parameter " + inQuotes(p.name) + " is already selected by parameters[" +
                       std::to_string(m_selectedBy[k]) + "]: each scene parameter may be optimised once");
      m_selectedBy[k] = entry;
      ExperimentParameter x;
      x.name = p.name;
      x.sceneIndex = k;
      x.group = group;
      x.range = validRange(p, nameField);
      if (narrowed) {
        const ParameterRange kindRange = x.range;
        x.range = intersect(kindRange, *narrowed);
        if (isEmpty(x.range))
          o.field("range").fail(describeRange(*narrowed) + " does not overlap the valid range " +
                                describeRange(kindRange) + " of parameter " + inQuotes(p.name) + " (" +
                                parameterKindName(p.kind) + ")");
      }
      x.initial = initial[m];
      requireInParameterRange(o, "initial", m, x, x.initial);
      if (truth) {
        x.truth = (*truth)[m];
        requireInParameterRange(o, "truth", m, x, *x.truth);
      }
      m_x.parameters.push_back(std::move(x));
      m_entryOf.push_back(entry);
    }
  }

  // The scene parameters a name or wildcard pattern selects, in scene order.
  std::vector<uint32_t> matchParameters(const JsonValue& field) {
    const std::string pattern = field.string();
    const Scene& scene = m_x.scene;
    const std::string sceneName = m_x.scenePath.filename().string();
    if (pattern.find('*') == std::string::npos) {
      const auto found = m_parameterIndex.find(pattern);
      if (found == m_parameterIndex.end())
        field.fail("unknown parameter " + inQuotes(pattern) + " in " + sceneName + parameterSuggestions(scene, pattern));
      return {found->second};
    }
    std::string stem = pattern;
    std::erase(stem, '*');
    if (!stem.empty() && !isValidParameterName(stem))
      field.fail("invalid name pattern " + inQuotes(pattern) +
                 " (names use letters, digits, '_', '-' and '.'; '*' matches any run of characters)");
    std::vector<uint32_t> matches;
    for (size_t k = 0; k < scene.parameters.size(); ++k)
      if (matchesWildcard(pattern, scene.parameters[k].name)) matches.push_back(uint32_t(k));
    if (matches.empty())
      field.fail(inQuotes(pattern) + " matches no parameter of " + sceneName +
                 parameterSuggestions(scene, pattern.substr(0, pattern.find('*'))));
    return matches;
  }

  // `initial` or `truth`: one number for every match, or an array with one number per match.
  static std::optional<std::vector<double>> valuesPerMatch(const JsonObject& o, std::string_view key, size_t count) {
    if (!o.has(key)) return std::nullopt;
    const JsonValue field = o.field(key);
    if (!field.json().is_array()) return std::vector<double>(count, field.number());
    if (field.json().size() != count)
      field.fail("wrong length: the name matches " + std::to_string(count) +
                 " parameter(s); give one number for all or one per parameter, got " +
                 std::to_string(field.json().size()) + " numbers");
    return field.numbers(count);
  }

  void requireInParameterRange(const JsonObject& o, std::string_view key, size_t match, const ExperimentParameter& x,
                               double value) const {
    if (x.range.contains(value)) return;
    const Parameter& p = m_x.scene.parameters[x.sceneIndex];
    std::string problem = std::string(key) + " value " + formatNumber(value) + " of parameter " + inQuotes(p.name) +
                          " (" + parameterKindName(p.kind) + ") is outside its valid range " + describeRange(x.range);
    if (!o.has(key)) absentField(o, key).fail(problem + " (0 is the default: give a value inside the range)");
    const JsonValue field = o.field(key);
    (field.json().is_array() ? field.element(match) : field).fail(problem);
  }

  // The kind's valid range; a gate_center parameter shifts every target's gate, so its range is
  // the intersection over the targets' gates.
  ParameterRange validRange(const Parameter& p, const JsonValue& where) const {
    if (p.kind != ParameterKind::GateCenter) return parameterRange(m_x.scene, p);
    ParameterRange range;
    bool gated = false;
    for (const Target& target : m_x.targets) {
      if (target.gate.type == GateType::Steady) continue;
      gated = true;
      Scene gateOnly;  // parameterRange reads nothing but the gate for gate_center
      gateOnly.gate = target.gate;
      range = intersect(range, parameterRange(gateOnly, p));
    }
    if (!gated)
      where.fail("gate_center parameter " + inQuotes(p.name) + " changes nothing: every target's gate is steady");
    return range;
  }

  // ---- loss, optimiser ----

  void parseLoss(const JsonValue& value) {
    const std::string type = typeOf(value, {"l2", "l1", "relative_l2"});
    std::vector<std::string_view> allowed = {"type"};
    if (type == "relative_l2") allowed.push_back("epsilon");
    const JsonObject o(value, allowed);
    LossSpec& loss = m_x.loss;
    loss.type = type == "l2" ? LossType::L2 : type == "l1" ? LossType::L1 : LossType::RelativeL2;
    loss.epsilon = o.number("epsilon", loss.epsilon);
    if (o.has("epsilon")) requireAbove(o.field("epsilon"), loss.epsilon, 0.0);
  }

  void parseOptimizer(const JsonValue& value) {
    const std::string type = typeOf(value, {"adam", "sgd"});
    std::vector<std::string_view> allowed = {"type", "learning_rate", "groups", "schedule"};
    if (type == "adam") allowed.insert(allowed.end(), {"beta1", "beta2", "epsilon", "uniform"});
    else allowed.push_back("momentum");
    const JsonObject o(value, allowed);
    OptimizerSpec& spec = m_x.optimizer;
    spec.type = type == "adam" ? OptimizerType::Adam : OptimizerType::Sgd;
    spec.learningRate = learningRate(o, spec.learningRate);
    spec.beta1 = unitInterval(o, "beta1", spec.beta1);
    spec.beta2 = unitInterval(o, "beta2", spec.beta2);
    spec.momentum = unitInterval(o, "momentum", spec.momentum);
    spec.epsilon = o.number("epsilon", spec.epsilon);
    if (o.has("epsilon")) requireAbove(o.field("epsilon"), spec.epsilon, 0.0);
    spec.uniform = o.boolean("uniform", spec.uniform);
    if (o.has("groups")) {
      const JsonValue groups = o.field("groups");
      if (!groups.json().is_object()) groups.fail("wrong type: expected an object mapping group names to {\"learning_rate\": ...}");
      for (const auto& item : groups.json().items()) {
        const JsonValue entry{&item.value(), m_file, groups.path + "." + item.key()};
        if (item.key() == "default")
          entry.fail("the group \"default\" (parameters without a group) takes optimizer.learning_rate");
        if (item.key().empty()) entry.fail("empty group name");
        spec.groupRates.emplace_back(item.key(), learningRate(JsonObject(entry, {"learning_rate"}), std::nullopt));
      }
    }
    if (o.has("schedule")) parseSchedule(o.field("schedule"));
  }

  static double learningRate(const JsonObject& o, std::optional<double> fallback) {
    if (!o.has("learning_rate") && fallback) return *fallback;
    const JsonValue field = o.field("learning_rate");
    const double rate = field.number();
    if (!(rate > 0)) field.fail("non-positive learning rate " + formatNumber(rate) + ": it must be > 0");
    return rate;
  }

  // beta1, beta2, momentum: in [0, 1).
  static double unitInterval(const JsonObject& o, std::string_view key, double fallback) {
    if (!o.has(key)) return fallback;
    const JsonValue field = o.field(key);
    const double value = field.number();
    if (!(value >= 0 && value < 1)) field.fail("out of range: " + formatNumber(value) + " is not in [0, 1)");
    return value;
  }

  void parseSchedule(const JsonValue& value) {
    const std::string type = typeOf(value, {"constant", "exponential", "step"});
    std::vector<std::string_view> allowed = {"type", "warmup"};
    if (type != "constant") allowed.push_back("decay");
    if (type == "step") allowed.push_back("every");
    const JsonObject o(value, allowed);
    ScheduleSpec& schedule = m_x.optimizer.schedule;
    schedule.type = type == "constant" ? ScheduleType::Constant
                    : type == "exponential" ? ScheduleType::Exponential
                                            : ScheduleType::Step;
    if (o.has("warmup")) schedule.warmup = o.field("warmup").uinteger(0, kMaxUint32);
    if (type == "constant") return;
    const JsonValue decay = o.field("decay");
    schedule.decay = decay.number();
    if (!(schedule.decay > 0 && schedule.decay <= 1))
      decay.fail("out of range: " + formatNumber(schedule.decay) + " is not in (0, 1]");
    if (type == "step") schedule.every = o.field("every").uinteger(1, kMaxUint32);
  }

  // Every group a parameter names is defined, and every defined group is used.
  void checkGroups() const {
    const auto& rates = m_x.optimizer.groupRates;
    std::set<std::string> used;
    for (const auto& [group, path] : m_groupFields) {
      used.insert(group);
      const std::string& name = group;  // clang before 16 cannot capture a structured binding
      const bool defined = std::any_of(rates.begin(), rates.end(), [&](const auto& r) { return r.first == name; });
      if (group != "default" && !defined)
        vktg::fail(m_file, path, "unknown group " + inQuotes(group) + " (define its learning rate in optimizer.groups)");
    }
    for (const auto& [group, rate] : rates)
      if (!used.count(group)) vktg::fail(m_file, "optimizer.groups." + group, "group " + inQuotes(group) + " is used by no parameter");
  }

  // ---- regularisers, preconditioner ----

  uint32_t shapeIndex(const JsonValue& field) const {
    const std::string name = field.string();
    const auto found = m_shapeIndex.find(name);
    if (found == m_shapeIndex.end()) field.fail("unknown shape " + inQuotes(name));
    return found->second;
  }

  // The optimised parameters that move vertices of `shape`, as indices into Experiment::parameters.
  std::vector<size_t> parametersMoving(uint32_t shape) const {
    std::vector<size_t> moving;
    const std::string& name = m_x.scene.shapes[shape].name;
    for (size_t i = 0; i < m_x.parameters.size(); ++i) {
      const Parameter& p = m_x.scene.parameters[m_x.parameters[i].sceneIndex];
      if (movesVertices(p.kind) && p.target == name) moving.push_back(i);
    }
    return moving;
  }

  void parseRegularizer(const JsonValue& value) {
    typeOf(value, {"laplacian"});
    const JsonObject o(value, {"type", "shape", "weight"});
    RegularizerSpec spec;
    spec.shape = shapeIndex(o.field("shape"));
    const JsonValue weight = o.field("weight");
    spec.weight = weight.number();
    requireAtLeast(weight, spec.weight, 0.0);
    const std::vector<size_t> moving = parametersMoving(spec.shape);
    const bool displaced = std::any_of(moving.begin(), moving.end(), [&](size_t i) {
      return m_x.scene.parameters[m_x.parameters[i].sceneIndex].kind == ParameterKind::Displace;
    });
    // Rigid motions leave the Laplacian energy unchanged: without a displacement it is a constant.
    if (!displaced)
      o.field("shape").fail("no optimised parameter displaces vertices of shape " +
                            inQuotes(m_x.scene.shapes[spec.shape].name) + ": the regulariser would be constant");
    m_x.regularizers.push_back(spec);
  }

  void parsePreconditioner(const JsonValue& value) {
    typeOf(value, {"large_steps"});
    const JsonObject o(value, {"type", "shape", "lambda"});
    PreconditionerSpec spec;
    const JsonValue shapeField = o.field("shape");
    spec.shape = shapeIndex(shapeField);
    const JsonValue lambda = o.field("lambda");
    spec.lambda = lambda.number();
    requireAbove(lambda, spec.lambda, 0.0);
    const Shape& shape = m_x.scene.shapes[spec.shape];
    const std::vector<size_t> moving = parametersMoving(spec.shape);
    if (moving.empty())
      shapeField.fail("no optimised parameter moves vertices of shape " + inQuotes(shape.name) + ": nothing to precondition");
    // The preconditioner smooths a gradient given per vertex and direction: one parameter per
    // displaced vertex and direction (a free vertex's x, y and z).
    std::map<std::array<float, 3>, std::vector<size_t>> displacedBy;  // direction -> per vertex
    for (size_t i : moving) {
      const Parameter& p = m_x.scene.parameters[m_x.parameters[i].sceneIndex];
      if (p.kind != ParameterKind::Displace || p.vertices.size() != 1)
        shapeField.fail("parameter " + inQuotes(p.name) + " (" + parameterKindName(p.kind) +
                        (p.kind == ParameterKind::Displace ? " of " + std::to_string(p.vertices.size()) + " vertices" : "") +
                        ") moves shape " + inQuotes(shape.name) +
                        ": large steps needs every optimised parameter of the shape to displace one vertex");
      const glm::vec3 direction = glm::normalize(p.axis);  // heights: the heightfield's scaled up
      std::vector<size_t>& along = displacedBy[{direction.x, direction.y, direction.z}];
      if (along.empty()) along.assign(shape.positions.size(), kUnselected);
      size_t& other = along[p.vertices.front()];
      if (other != kUnselected)
        shapeField.fail("vertex " + std::to_string(p.vertices.front()) + " of shape " + inQuotes(shape.name) +
                        " is displaced by both " + inQuotes(m_x.parameters[other].name) + " and " + inQuotes(p.name) +
                        " along one direction: large steps needs one parameter per vertex and direction");
      other = i;
    }
    m_x.preconditioner = spec;
  }

  // ---- render, stop ----

  void parseRender(const JsonValue& value) {
    const JsonObject o(value,
                       {"spp", "spp_interior", "interior_passes", "spp_edge", "spp_boundary", "spp_boundary_camera", "terms",
                        "antithetic", "nee", "max_depth", "gradient", "fd_step"});
    BudgetSpec& b = m_x.budget;
    b.sppPrimal = o.uinteger("spp", b.sppPrimal, 1, kMaxSpp);
    b.sppInterior = o.uinteger("spp_interior", b.sppInterior, 1, kMaxSpp);
    b.interiorPasses = o.uinteger("interior_passes", b.interiorPasses, 1, kMaxInteriorPasses);
    if (b.sppInterior % b.interiorPasses != 0)
      o.field("interior_passes").fail("must divide spp_interior (" + std::to_string(b.sppInterior) + ")");
    // Samples per pixel on average, fractions allowed (fewer samples than pixels, spread over
    // them), or "auto": the term pilot's choice.
    auto termSpp = [&](const char* key, double& spp, bool& pilot) {
      if (!o.has(key)) return;
      const JsonValue v = o.field(key);
      if (v.json().is_string()) {
        v.oneOf({"auto"});
        pilot = true;
        return;
      }
      if (!v.json().is_number()) v.fail("wrong type: expected a number of samples per pixel or \"auto\"");
      spp = v.json().get<double>();
      requireAbove(v, spp, 0.0);
      requireInRange(v, spp, 0.0, double(kMaxSpp));
    };
    termSpp("spp_edge", b.sppEdge, b.sppEdgeAuto);
    termSpp("spp_boundary", b.sppBoundary, b.sppBoundaryAuto);
    b.sppBoundaryCamera = b.sppBoundary, b.sppBoundaryCameraAuto = b.sppBoundaryAuto;
    if (o.has("spp_boundary_camera")) {
      b.sppBoundaryCameraAuto = false;
      termSpp("spp_boundary_camera", b.sppBoundaryCamera, b.sppBoundaryCameraAuto);
    }
    if (o.has("terms")) parseTerms(o.field("terms"));
    if (o.has("antithetic")) b.antithetic = o.field("antithetic").oneOf({"auto", "on", "off"});
    if (o.has("nee")) b.nee = readNeeMode(o.field("nee"));
    b.maxDepth = o.uinteger("max_depth", b.maxDepth, 1, kMaxDepth);
    if (o.has("gradient")) b.finiteDifferences = o.field("gradient").oneOf({"adjoint", "finite_differences"}) == "finite_differences";
    const std::optional<double> step = positive(o, "fd_step");
    if (b.finiteDifferences && !step) value.fail("\"gradient\": \"finite_differences\" needs \"fd_step\", the step in parameter units");
    if (!b.finiteDifferences && step) o.field("fd_step").fail("only used with \"gradient\": \"finite_differences\"");
    if (b.finiteDifferences && o.has("interior_passes")) o.field("interior_passes").fail("only used with adjoint gradients");
    b.finiteDifferenceStep = step.value_or(0.0);
  }

  void parseTerms(const JsonValue& value) {
    BudgetSpec& b = m_x.budget;
    if (value.json().is_string()) {
      value.oneOf({"auto"});
      return;
    }
    if (!value.json().is_array()) value.fail("wrong type: expected \"auto\" or a list of terms (interior, edge, pathlength)");
    if (value.json().empty()) value.fail("empty list: name at least one term, or \"auto\"");
    b.interior = b.edge = b.pathLength = false;
    for (size_t i = 0; i < value.json().size(); ++i) {
      const JsonValue element = value.element(i);
      const std::string term = element.oneOf({termName(Term::Interior), termName(Term::Edge), termName(Term::PathLength)});
      bool& on = term == termName(Term::Interior) ? b.interior : term == termName(Term::Edge) ? b.edge : b.pathLength;
      if (on) element.fail("term " + inQuotes(term) + " listed twice");
      on = true;
    }
  }

  void parseStop(const JsonValue& value) {
    const JsonObject o(value, {"iterations", "loss_below", "parameter_error_below", "seconds"});
    StopSpec& stop = m_x.stop;
    stop.iterations = o.uinteger("iterations", stop.iterations, 1, kMaxUint32);
    stop.lossBelow = positive(o, "loss_below");
    stop.parameterErrorBelow = positive(o, "parameter_error_below");
    stop.seconds = positive(o, "seconds");
    const bool anyTruth = std::any_of(m_x.parameters.begin(), m_x.parameters.end(),
                                      [](const ExperimentParameter& p) { return p.truth.has_value(); });
    if (stop.parameterErrorBelow && !anyTruth)
      o.field("parameter_error_below").fail("the parameter error needs the true value of some parameter (\"truth\" in parameters)");
  }

  static std::optional<double> positive(const JsonObject& o, std::string_view key) {
    if (!o.has(key)) return std::nullopt;
    const double value = o.field(key).number();
    requireAbove(o.field(key), value, 0.0);
    return value;
  }

  // Rendering a target at the truth needs the true value of every optimised parameter.
  void checkTruthForSynthesis() const {
    for (size_t t = 0; t < m_x.targets.size(); ++t) {
      if (!m_x.targets[t].synthesize) continue;
      for (size_t i = 0; i < m_x.parameters.size(); ++i)
        if (!m_x.parameters[i].truth)
          vktg::fail(m_file, "targets[" + std::to_string(m_x.targets[t].entry) + "].image.synthesize",
                     "rendering the target needs the true value of every parameter, but parameters[" +
                         std::to_string(m_entryOf[i]) + "] (" + inQuotes(m_x.parameters[i].name) + ") has no \"truth\"");
    }
  }

  std::string m_file;
  fs::path m_baseDir;
  SceneDefines m_defines;  // -D: over the file's own
  Experiment m_x;
  std::optional<Scan> m_sceneCapture;  // a Mitsuba XML scene's nlos_capture_meter scan
  std::unordered_map<std::string, uint32_t> m_parameterIndex;  // scene parameter name -> index
  std::unordered_map<std::string, uint32_t> m_shapeIndex;      // shape name -> index
  std::vector<size_t> m_selectedBy;  // per scene parameter: the "parameters" entry that selected it
  std::vector<size_t> m_entryOf;     // per experiment parameter: its "parameters" entry
  std::vector<std::pair<std::string, std::string>> m_groupFields;  // group named, JSON path naming it
};

}  // namespace

Experiment parseExperimentJson(const std::string& text, const std::string& file, const std::filesystem::path& baseDir,
                               const SceneDefines& defines) {
  const Json json = parseJsonText(text, file);
  Experiment experiment = ExperimentParser(file, baseDir, defines).parse(json);
  experiment.text = text;
  return experiment;
}

Experiment loadExperiment(const std::filesystem::path& path, const SceneDefines& defines) {
  Experiment experiment = parseExperimentJson(readTextFile(path), path.string(), path.parent_path(), defines);
  experiment.source = path;
  return experiment;
}

}  // namespace vktg
