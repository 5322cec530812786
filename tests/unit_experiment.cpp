// Experiment files (docs/optimize.md): the complete example parsed field by field, defaults,
// wildcard selection, views and gates of targets, target images, and every class of bad input
// as one table whose rows each edit a valid base experiment in one place.
#include <filesystem>
#include <functional>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "opt/experiment.h"
#include "support/file_test.h"
#include "support/table_case_name.h"
#include "vktg/error.h"

namespace vktg {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using test::expectError;

const fs::path kData = fs::path(VKTG_TEST_DATA) / "optimize";
const char* kFile = "bad_experiment.json";

json baseExperiment() {
  return json::parse(R"({
    "version": 1,
    "scene": "terrain.json",
    "parameters": [
      {"name": "h*", "initial": 0, "truth": 0, "group": "heights", "range": [-0.5, 0.5]},
      {"name": "grey", "initial": 0.1, "truth": 0}
    ],
    "targets": [
      {"name": "front", "image": "front.exr"},
      {"name": "above", "view": {"position": [0, 3, 0.5], "look_at": [0, 0, 0], "up": [0, 0, -1],
                                 "lights": {"laser": [0, 3, 0.5]}},
       "gate": {"type": "box", "a": 2, "b": 6}, "image": {"synthesize": {"spp": 64}}}
    ],
    "loss": {"type": "l2"},
    "optimizer": {"type": "adam", "learning_rate": 0.01, "groups": {"heights": {"learning_rate": 0.001}},
                  "schedule": {"type": "exponential", "decay": 0.99}},
    "regularizers": [{"type": "laplacian", "shape": "terrain", "weight": 0.1}],
    "preconditioner": {"type": "large_steps", "shape": "terrain", "lambda": 2},
    "render": {"spp": 8, "terms": "auto"},
    "stop": {"iterations": 10, "parameter_error_below": 0.01}
  })");
}

std::string errorFor(const json& experiment) {
  try {
    parseExperimentJson(experiment.dump(), kFile, kData);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(ExperimentErrors, BaseExperimentIsValid) { EXPECT_EQ(errorFor(baseExperiment()), ""); }

struct BadCase {
  const char* name;
  std::function<void(json&)> edit;
  const char* field;    // JSON path the message must name
  const char* keyword;  // the problem the message must name
};

json& entry(json& j, size_t i) { return j["parameters"][i]; }
json& target(json& j, size_t i) { return j["targets"][i]; }
json& view(json& j) { return j["targets"][1]["view"]; }

const BadCase kCases[] = {
    // Top level.
    {"unknown top-level field", [](json& j) { j["colour"] = 1; }, "colour", "unknown field"},
    {"missing version", [](json& j) { j.erase("version"); }, "version", "missing required field"},
    {"future version", [](json& j) { j["version"] = 2; }, "version", "unsupported version"},
    {"description not a string", [](json& j) { j["description"] = 3; }, "description", "wrong type"},
    {"missing scene", [](json& j) { j.erase("scene"); }, "scene", "missing required field"},
    {"scene not found", [](json& j) { j["scene"] = "nowhere.json"; }, "scene", "file not found"},
    {"scene of unknown kind", [](json& j) { j["scene"] = "front.exr"; }, "scene", "unknown scene file extension"},
    {"empty scene path", [](json& j) { j["scene"] = ""; }, "scene", "empty path"},
    {"scene object without a file", [](json& j) { j["scene"] = {{"defines", json::object()}}; }, "scene.file",
     "missing required field"},
    {"unknown field of the scene object", [](json& j) { j["scene"] = {{"file", "terrain.json"}, {"colour", 1}}; }, "scene.colour",
     "unknown field"},
    {"defines not an object", [](json& j) { j["scene"] = {{"file", "terrain.json"}, {"defines", 3}}; }, "scene.defines",
     "wrong type"},
    {"define of a bad name", [](json& j) { j["scene"] = {{"file", "terrain.json"}, {"defines", {{"a b", "1"}}}}; },
     "scene.defines.a b", "letters, digits"},
    {"define of an array", [](json& j) { j["scene"] = {{"file", "terrain.json"}, {"defines", {{"a", {1}}}}}; }, "scene.defines.a",
     "wrong type"},
    {"scene parameters for a JSON scene",
     [](json& j) { j["scene"] = {{"file", "terrain.json"}, {"parameters", json::array({{{"type", "gate_center"}, {"name", "t"}}})}}; },
     "scene.parameters", "in its own file"},
    {"defines for a JSON scene", [](json& j) { j["scene"] = {{"file", "terrain.json"}, {"defines", {{"a", 1}}}}; }, "scene.file",
     "Mitsuba XML"},
    {"zero checkpoint interval", [](json& j) { j["checkpoint_every"] = 0; }, "checkpoint_every", "out of range"},
    {"zero image interval", [](json& j) { j["images_every"] = 0; }, "images_every", "out of range"},
    {"negative seed", [](json& j) { j["seed"] = -1; }, "seed", "out of range"},
    {"fractional seed", [](json& j) { j["seed"] = 1.5; }, "seed", "integer"},
    // Parameters.
    {"missing parameters", [](json& j) { j.erase("parameters"); }, "parameters", "missing required field"},
    {"parameters not an array", [](json& j) { j["parameters"] = json::object(); }, "parameters", "wrong type"},
    {"no parameters", [](json& j) { j["parameters"] = json::array(); }, "parameters", "no parameters"},
    {"unknown parameter field", [](json& j) { entry(j, 1)["inital"] = 0.1; }, "parameters[1].inital", "unknown field"},
    {"missing parameter name", [](json& j) { entry(j, 1).erase("name"); }, "parameters[1].name", "missing required field"},
    {"unknown parameter name", [](json& j) { entry(j, 1)["name"] = "gray"; }, "parameters[1].name", "did you mean: grey"},
    {"wildcard matching nothing", [](json& j) { entry(j, 1)["name"] = "z*"; }, "parameters[1].name", "matches no parameter"},
    {"invalid name pattern", [](json& j) { entry(j, 1)["name"] = "g,*"; }, "parameters[1].name", "invalid name pattern"},
    {"parameter selected twice",
     [](json& j) { j["parameters"].push_back({{"name", "h3"}, {"truth", 0}, {"group", "heights"}}); },
     "parameters[2].name", "already selected by parameters[0]"},
    {"initial outside the kind's range", [](json& j) { entry(j, 1)["initial"] = 0.6; }, "parameters[1].initial",
     "outside its valid range [-0.5, 0.5]"},
    {"truth outside the narrowed range", [](json& j) { entry(j, 0)["truth"] = json::array({0, 0, 0, 0.7, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0}); },
     "parameters[0].truth[3]", "outside its valid range"},
    {"default initial outside the range", [](json& j) { entry(j, 0).erase("initial"); entry(j, 0)["range"] = {0.1, 0.5}; entry(j, 0)["truth"] = 0.2; },
     "parameters[0].initial", "0 is the default"},
    {"range outside the kind's range", [](json& j) { entry(j, 1)["range"] = {0.6, 0.9}; }, "parameters[1].range", "does not overlap"},
    {"empty range", [](json& j) { entry(j, 1)["range"] = {0.3, 0.1}; }, "parameters[1].range", "empty range"},
    {"range of one number", [](json& j) { entry(j, 1)["range"] = {0.3}; }, "parameters[1].range", "wrong length"},
    {"initial list of wrong length", [](json& j) { entry(j, 0)["initial"] = {0, 0}; }, "parameters[0].initial", "matches 16"},
    {"initial as string", [](json& j) { entry(j, 1)["initial"] = "0.1"; }, "parameters[1].initial", "wrong type"},
    {"initial null", [](json& j) { entry(j, 1)["initial"] = nullptr; }, "parameters[1].initial", "wrong type"},
    {"truth list element not a number", [](json& j) { entry(j, 0)["truth"] = json::array({0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, true}); },
     "parameters[0].truth[15]", "wrong type"},
    {"gate centre under steady gates",
     [](json& j) {
       j["parameters"].push_back({{"name", "t0"}, {"truth", 0}});
       target(j, 0)["gate"] = {{"type", "steady"}};
       target(j, 1)["gate"] = {{"type", "steady"}};
     },
     "parameters[2].name", "every target's gate is steady"},
    {"gate centre moving a gate below zero",
     [](json& j) { j["parameters"].push_back({{"name", "t0"}, {"truth", -2.5}}); }, "parameters[2].truth",
     "outside its valid range [-2, inf)"},
    {"unknown group", [](json& j) { entry(j, 1)["group"] = "albedo"; }, "parameters[1].group", "unknown group"},
    {"empty group", [](json& j) { entry(j, 1)["group"] = ""; }, "parameters[1].group", "empty group name"},
    // Targets.
    {"missing targets", [](json& j) { j.erase("targets"); }, "targets", "missing required field"},
    {"no targets", [](json& j) { j["targets"] = json::array(); }, "targets", "no targets"},
    {"unknown target field", [](json& j) { target(j, 0)["wieght"] = 1; }, "targets[0].wieght", "unknown field"},
    {"duplicate target name", [](json& j) { target(j, 1)["name"] = "front"; }, "targets[1].name", "duplicate target name"},
    {"target name with a space", [](json& j) { target(j, 1)["name"] = "top view"; }, "targets[1].name", "invalid target name"},
    {"missing image", [](json& j) { target(j, 0).erase("image"); }, "targets[0].image", "missing required field"},
    {"image not found", [](json& j) { target(j, 0)["image"] = "nowhere.exr"; }, "targets[0].image", "file not found"},
    {"image is a folder", [](json& j) { target(j, 0)["image"] = "."; }, "targets[0].image", "not a regular file"},
    {"image of wrong type", [](json& j) { target(j, 0)["image"] = 3; }, "targets[0].image", "wrong type"},
    {"empty image path", [](json& j) { target(j, 0)["image"] = ""; }, "targets[0].image", "empty path"},
    {"unknown image field", [](json& j) { target(j, 1)["image"]["render"] = 1; }, "targets[1].image.render", "unknown field"},
    {"unknown synthesis field", [](json& j) { target(j, 1)["image"]["synthesize"]["sed"] = 1; },
     "targets[1].image.synthesize.sed", "unknown field"},
    {"synthesis with zero spp", [](json& j) { target(j, 1)["image"]["synthesize"]["spp"] = 0; },
     "targets[1].image.synthesize.spp", "out of range"},
    {"synthesis without a truth", [](json& j) { entry(j, 1).erase("truth"); j["stop"].erase("parameter_error_below"); },
     "targets[1].image.synthesize", "parameters[1] (\"grey\") has no \"truth\""},
    {"zero weight", [](json& j) { target(j, 0)["weight"] = 0; }, "targets[0].weight", "out of range"},
    {"negative weight", [](json& j) { target(j, 0)["weight"] = -1; }, "targets[0].weight", "out of range"},
    {"gate with a after b", [](json& j) { target(j, 1)["gate"] = {{"type", "box"}, {"a", 5}, {"b", 1}}; }, "targets[1].gate", "a must be < b"},
    {"bad gate spec", [](json& j) { target(j, 1)["gate"] = {{"spec", "box:1"}}; }, "targets[1].gate.spec", "box:A,B"},
    {"unknown gate type", [](json& j) { target(j, 1)["gate"] = {{"type", "boxcar"}}; }, "targets[1].gate.type", "unknown type"},
    {"unknown view field", [](json& j) { view(j)["pos"] = {0, 1, 0}; }, "targets[1].view.pos", "unknown field"},
    {"sensor normal on a perspective camera", [](json& j) { view(j)["normal"] = {0, -1, 0}; }, "targets[1].view.normal",
     "applies to point sensors"},
    {"view looking at itself", [](json& j) { view(j)["look_at"] = {0, 3, 0.5}; }, "targets[1].view.look_at",
     "look_at equals position"},
    {"moved eye onto the look-at point", [](json& j) { view(j).erase("look_at"); view(j)["position"] = {0, 0, 0}; },
     "targets[1].view.position", "look_at equals position"},
    {"up along the view", [](json& j) { view(j)["up"] = {0, -1, -0.5 / 3}; }, "targets[1].view.up", "parallel"},
    {"scene's up along the new view", [](json& j) { view(j).erase("up"); view(j)["position"] = {0, 3, 0}; },
     "targets[1].view.look_at", "parallel"},
    {"zero up", [](json& j) { view(j)["up"] = {0, 0, 0}; }, "targets[1].view.up", "must not be zero"},
    {"view position too short", [](json& j) { view(j)["position"] = {0, 1}; }, "targets[1].view.position", "wrong length"},
    {"unknown light", [](json& j) { view(j)["lights"] = {{"lamp", {0, 1, 0}}}; }, "targets[1].view.lights.lamp",
     "unknown point light \"lamp\" (the scene's point lights: laser)"},
    {"light position too short", [](json& j) { view(j)["lights"]["laser"] = {0, 1}; }, "targets[1].view.lights.laser", "wrong length"},
    {"lights not an object", [](json& j) { view(j)["lights"] = json::array(); }, "targets[1].view.lights", "wrong type"},
    // Loss.
    {"unknown loss type", [](json& j) { j["loss"]["type"] = "l3"; }, "loss.type", "unknown type"},
    {"epsilon of an l2 loss", [](json& j) { j["loss"]["epsilon"] = 0.1; }, "loss.epsilon", "unknown field"},
    {"zero relative epsilon", [](json& j) { j["loss"] = {{"type", "relative_l2"}, {"epsilon", 0}}; }, "loss.epsilon", "out of range"},
    // Optimiser.
    {"unknown optimizer type", [](json& j) { j["optimizer"]["type"] = "rmsprop"; }, "optimizer.type", "unknown type"},
    {"zero learning rate", [](json& j) { j["optimizer"]["learning_rate"] = 0; }, "optimizer.learning_rate",
     "non-positive learning rate"},
    {"negative group learning rate", [](json& j) { j["optimizer"]["groups"]["heights"]["learning_rate"] = -0.1; },
     "optimizer.groups.heights.learning_rate", "non-positive learning rate"},
    {"group without learning rate", [](json& j) { j["optimizer"]["groups"]["heights"] = json::object(); },
     "optimizer.groups.heights.learning_rate", "missing required field"},
    {"unused group", [](json& j) { j["optimizer"]["groups"]["extra"] = {{"learning_rate", 0.1}}; }, "optimizer.groups.extra",
     "used by no parameter"},
    {"default group defined", [](json& j) { j["optimizer"]["groups"]["default"] = {{"learning_rate", 0.1}}; },
     "optimizer.groups.default", "optimizer.learning_rate"},
    {"groups not an object", [](json& j) { j["optimizer"]["groups"] = json::array(); }, "optimizer.groups", "wrong type"},
    {"momentum for adam", [](json& j) { j["optimizer"]["momentum"] = 0.9; }, "optimizer.momentum", "unknown field"},
    {"beta2 for sgd", [](json& j) { j["optimizer"]["type"] = "sgd"; j["optimizer"]["beta2"] = 0.9; }, "optimizer.beta2",
     "unknown field"},
    {"beta1 of one", [](json& j) { j["optimizer"]["beta1"] = 1; }, "optimizer.beta1", "out of range"},
    {"uniform for sgd", [](json& j) { j["optimizer"]["type"] = "sgd"; j["optimizer"]["uniform"] = true; }, "optimizer.uniform",
     "unknown field"},
    {"uniform not a boolean", [](json& j) { j["optimizer"]["uniform"] = 1; }, "optimizer.uniform", "wrong type"},
    {"negative momentum", [](json& j) { j["optimizer"] = {{"type", "sgd"}, {"momentum", -0.1}, {"groups", {{"heights", {{"learning_rate", 1}}}}}}; },
     "optimizer.momentum", "out of range"},
    {"zero adam epsilon", [](json& j) { j["optimizer"]["epsilon"] = 0; }, "optimizer.epsilon", "out of range"},
    {"unknown schedule", [](json& j) { j["optimizer"]["schedule"]["type"] = "cosine"; }, "optimizer.schedule.type", "unknown type"},
    {"zero decay", [](json& j) { j["optimizer"]["schedule"]["decay"] = 0; }, "optimizer.schedule.decay", "out of range"},
    {"growing decay", [](json& j) { j["optimizer"]["schedule"]["decay"] = 1.5; }, "optimizer.schedule.decay", "out of range"},
    {"missing decay", [](json& j) { j["optimizer"]["schedule"].erase("decay"); }, "optimizer.schedule.decay",
     "missing required field"},
    {"step without every", [](json& j) { j["optimizer"]["schedule"]["type"] = "step"; }, "optimizer.schedule.every",
     "missing required field"},
    {"step every zero", [](json& j) { j["optimizer"]["schedule"] = {{"type", "step"}, {"decay", 0.5}, {"every", 0}}; },
     "optimizer.schedule.every", "out of range"},
    {"negative warmup", [](json& j) { j["optimizer"]["schedule"]["warmup"] = -1; }, "optimizer.schedule.warmup", "out of range"},
    {"every of an exponential schedule", [](json& j) { j["optimizer"]["schedule"]["every"] = 5; }, "optimizer.schedule.every",
     "unknown field"},
    // Regularisers and preconditioner.
    {"unknown regularizer", [](json& j) { j["regularizers"][0]["type"] = "tv"; }, "regularizers[0].type", "unknown type"},
    {"regularizer of an unknown shape", [](json& j) { j["regularizers"][0]["shape"] = "hill"; }, "regularizers[0].shape",
     "unknown shape"},
    {"negative regularizer weight", [](json& j) { j["regularizers"][0]["weight"] = -1; }, "regularizers[0].weight", "out of range"},
    {"regularizer without weight", [](json& j) { j["regularizers"][0].erase("weight"); }, "regularizers[0].weight",
     "missing required field"},
    {"regularizer of an undisplaced shape",
     [](json& j) { j["parameters"].erase(0); j.erase("preconditioner"); j["optimizer"].erase("groups"); },
     "regularizers[0].shape", "would be constant"},
    {"unknown preconditioner", [](json& j) { j["preconditioner"]["type"] = "jacobi"; }, "preconditioner.type", "unknown type"},
    {"zero lambda", [](json& j) { j["preconditioner"]["lambda"] = 0; }, "preconditioner.lambda", "out of range"},
    {"preconditioner of an unmoved shape",
     [](json& j) { j["parameters"].erase(0); j.erase("regularizers"); j["optimizer"].erase("groups"); },
     "preconditioner.shape", "nothing to precondition"},
    {"preconditioner with a translation", [](json& j) { j["parameters"].push_back({{"name", "shift"}, {"truth", 0}}); },
     "preconditioner.shape", "parameter \"shift\" (translate)"},
    {"preconditioner with a two-vertex displacement", [](json& j) { j["parameters"].push_back({{"name", "bump"}, {"truth", 0}}); },
     "preconditioner.shape", "displace of 2 vertices"},
    {"preconditioner with a vertex moved twice", [](json& j) { j["parameters"].push_back({{"name", "lift5"}, {"truth", 0}}); },
     "preconditioner.shape", "vertex 5 of shape \"terrain\" is displaced by both \"h5\" and \"lift5\" along one direction"},
    // Render budget.
    {"unknown render field", [](json& j) { j["render"]["samples"] = 4; }, "render.samples", "unknown field"},
    {"zero spp", [](json& j) { j["render"]["spp"] = 0; }, "render.spp", "out of range"},
    {"zero edge spp", [](json& j) { j["render"]["spp_edge"] = 0; }, "render.spp_edge", "out of range"},
    {"edge spp word", [](json& j) { j["render"]["spp_edge"] = "pilot"; }, "render.spp_edge", "unknown value"},
    {"negative boundary spp", [](json& j) { j["render"]["spp_boundary"] = -0.5; }, "render.spp_boundary", "out of range"},
    {"huge camera spp", [](json& j) { j["render"]["spp_boundary_camera"] = 1e12; }, "render.spp_boundary_camera", "out of range"},
    {"boundary spp of wrong type", [](json& j) { j["render"]["spp_boundary"] = true; }, "render.spp_boundary", "wrong type"},
    {"camera boundary spp word", [](json& j) { j["render"]["spp_boundary_camera"] = "pilot"; }, "render.spp_boundary_camera",
     "unknown value"},
    {"zero camera boundary spp", [](json& j) { j["render"]["spp_boundary_camera"] = 0; }, "render.spp_boundary_camera",
     "out of range"},
    {"terms word", [](json& j) { j["render"]["terms"] = "all"; }, "render.terms", "unknown value"},
    {"no terms", [](json& j) { j["render"]["terms"] = json::array(); }, "render.terms", "empty list"},
    {"unknown term", [](json& j) { j["render"]["terms"] = {"edges"}; }, "render.terms[0]", "unknown value"},
    {"term twice", [](json& j) { j["render"]["terms"] = {"edge", "interior", "edge"}; }, "render.terms[2]", "listed twice"},
    {"terms of wrong type", [](json& j) { j["render"]["terms"] = 3; }, "render.terms", "wrong type"},
    {"unknown antithetic mode", [](json& j) { j["render"]["antithetic"] = "yes"; }, "render.antithetic", "unknown value"},
    {"unknown nee mode", [](json& j) { j["render"]["nee"] = "fast"; }, "render.nee", "unknown value"},
    {"zero max depth", [](json& j) { j["render"]["max_depth"] = 0; }, "render.max_depth", "out of range"},
    {"unknown gradient", [](json& j) { j["render"]["gradient"] = "numerical"; }, "render.gradient", "unknown value"},
    {"finite differences without a step", [](json& j) { j["render"]["gradient"] = "finite_differences"; }, "render", "needs \"fd_step\""},
    {"zero finite-difference step", [](json& j) { j["render"]["gradient"] = "finite_differences"; j["render"]["fd_step"] = 0; }, "render.fd_step", "out of range"},
    {"step without finite differences", [](json& j) { j["render"]["fd_step"] = 0.01; }, "render.fd_step", "only used with"},
    {"no interior pass", [](json& j) { j["render"]["interior_passes"] = 0; }, "render.interior_passes", "out of range"},
    {"interior passes not dividing the samples", [](json& j) { j["render"]["spp_interior"] = 16; j["render"]["interior_passes"] = 3; },
     "render.interior_passes", "must divide spp_interior (16)"},
    {"interior passes with finite differences",
     [](json& j) { j["render"]["gradient"] = "finite_differences"; j["render"]["fd_step"] = 0.01; j["render"]["interior_passes"] = 2; },
     "render.interior_passes", "only used with adjoint gradients"},
    // Stopping rules.
    {"zero iterations", [](json& j) { j["stop"]["iterations"] = 0; }, "stop.iterations", "out of range"},
    {"unknown stop field", [](json& j) { j["stop"]["minutes"] = 1; }, "stop.minutes", "unknown field"},
    {"zero loss threshold", [](json& j) { j["stop"]["loss_below"] = 0; }, "stop.loss_below", "out of range"},
    {"negative time limit", [](json& j) { j["stop"]["seconds"] = -5; }, "stop.seconds", "out of range"},
    {"parameter error without a truth",
     [](json& j) {
       entry(j, 0).erase("truth");
       entry(j, 1).erase("truth");
       target(j, 1)["image"] = "front.exr";
     },
     "stop.parameter_error_below", "true value"},
};

class ExperimentErrorCase : public testing::TestWithParam<BadCase> {};

TEST_P(ExperimentErrorCase, NamesFileFieldAndProblem) {
  json experiment = baseExperiment();
  GetParam().edit(experiment);
  const std::string message = errorFor(experiment);
  ASSERT_FALSE(message.empty()) << "accepted: " << experiment.dump();
  EXPECT_EQ(message.rfind(std::string(kFile) + ": ", 0), 0u) << message;
  EXPECT_NE(message.find(std::string(GetParam().field) + ":"), std::string::npos) << message;
  EXPECT_NE(message.find(GetParam().keyword), std::string::npos) << message;
}

INSTANTIATE_TEST_SUITE_P(Table, ExperimentErrorCase, testing::ValuesIn(kCases), test::tableCaseName<BadCase>);

// A Mitsuba XML scene with its "defines", over which the command line's -D wins. The XML scene
// has no parameters, so the first parameter of the experiment fails: after the scene loaded.
TEST(ExperimentErrors, MitsubaSceneTakesDefines) {
  json j = baseExperiment();
  j["scene"] = {{"file", "../mitsuba/nlos_confocal.xml"}, {"defines", {{"grid", 4}, {"spp", "8"}}}};
  j["targets"] = json::array({{{"name", "front"}, {"image", "front.exr"}}});
  auto message = [&](const SceneDefines& defines) {
    try {
      parseExperimentJson(j.dump(), kFile, kData, defines);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(message({}).find("\"h*\" matches no parameter of nlos_confocal.xml"), std::string::npos) << message({});
  EXPECT_NE(message({{"grid", "x"}}).find("is not an integer"), std::string::npos) << message({{"grid", "x"}});
  EXPECT_NE(message({{"nothing", "1"}}).find("-D nothing"), std::string::npos) << message({{"nothing", "1"}});
}

// The parameters of a Mitsuba XML scene come from the experiment's scene object, bound to the
// XML's ids and checked as a JSON scene's are.
TEST(ExperimentErrors, MitsubaSceneParametersNameTheirField) {
  json j = baseExperiment();
  j["targets"] = json::array({{{"name", "front"}, {"image", "front.exr"}}});
  auto message = [&](const json& parameter) {
    j["scene"] = {{"file", "../mitsuba/nlos_confocal.xml"}, {"parameters", json::array({parameter})}};
    try {
      parseExperimentJson(j.dump(), kFile, kData);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  std::string m = message({{"name", "y"}, {"type", "translate"}, {"shape", "nowhere"}, {"axis", {0, 1, 0}}});
  EXPECT_NE(m.find(std::string(kFile) + ": scene.parameters[0].shape: unknown shape \"nowhere\""), std::string::npos) << m;
  m = message({{"name", "y"}, {"type", "translate"}, {"shape", "hidden"}, {"axis", {0, 0, 0}}});
  EXPECT_NE(m.find("scene.parameters[0].axis: zero axis"), std::string::npos) << m;
  // Bound: the experiment's first parameter, "h*", is now what fails.
  m = message({{"name", "y"}, {"type", "translate"}, {"shape", "hidden"}, {"axis", {0, 1, 0}}});
  EXPECT_NE(m.find("\"h*\" matches no parameter of nlos_confocal.xml"), std::string::npos) << m;
}

TEST(ExperimentErrors, SyntaxAndDuplicateKeysAndRoot) {
  expectError([] { parseExperimentJson("{\n  \"version\": 1,\n  ]\n}", kFile, kData); }, {kFile, "syntax error", "line 3"});
  const std::string text = baseExperiment().dump();
  expectError([&] { parseExperimentJson("{\"seed\": 1, \"seed\": 2, " + text.substr(1), kFile, kData); },
              {kFile, "seed: duplicate field"});
  expectError([] { parseExperimentJson("[1]", kFile, kData); }, {kFile, "wrong type"});
}

class ExperimentFiles : public test::TempDirTest {};

TEST_F(ExperimentFiles, SceneErrorsNameBothFiles) {
  const fs::path dir = m_dir;
  test::writePlain(dir / "broken.json", R"({"version": 1, "camera": {"type": "pinhole"}})");
  json experiment = baseExperiment();
  experiment["scene"] = "broken.json";
  expectError([&] { parseExperimentJson(experiment.dump(), kFile, dir); },
              {kFile, "scene: ", (dir / "broken.json").string(), "camera.type", "unknown type"});
}

TEST(Experiment, CompleteExampleParsesFieldByField) {
  const Experiment x = loadExperiment(kData / "complete.json");
  EXPECT_EQ(x.source, kData / "complete.json");
  EXPECT_EQ(x.text, test::readAll(kData / "complete.json"));
  EXPECT_EQ(x.scenePath, kData / "terrain.json");
  EXPECT_EQ(x.scene.shapes.at(0).name, "terrain");

  ASSERT_EQ(x.parameters.size(), 18u);
  for (size_t k = 0; k < 16; ++k) {
    const ExperimentParameter& h = x.parameters[k];
    EXPECT_EQ(h.name, "h" + std::to_string(k));
    EXPECT_EQ(h.sceneIndex, k);
    EXPECT_EQ(h.group, "heights");
    EXPECT_EQ(h.initial, (k == 5 || k == 6 || k == 9 || k == 10) ? -0.1 : 0.0);
    EXPECT_EQ(h.truth, 0.0);
    EXPECT_EQ(h.range.low, -0.5);
    EXPECT_EQ(h.range.high, 0.5);
    EXPECT_FALSE(h.range.lowOpen || h.range.highOpen);
  }
  const ExperimentParameter& grey = x.parameters[16];
  EXPECT_EQ(grey.name, "grey");
  EXPECT_EQ(grey.sceneIndex, 16u);
  EXPECT_EQ(grey.initial, 0.2);
  EXPECT_EQ(grey.truth, 0.1);
  EXPECT_EQ(grey.group, "default");
  EXPECT_EQ(grey.range.low, -0.5);  // albedo 0.5 + θ in [0, 1]
  EXPECT_EQ(grey.range.high, 0.5);
  const ExperimentParameter& t0 = x.parameters[17];
  EXPECT_EQ(t0.name, "t0");
  EXPECT_EQ(t0.group, "calibration");
  EXPECT_EQ(t0.initial, 0.05);
  // Both gates start at 2 m: the gate may move back by 2 m at most.
  EXPECT_EQ(t0.range.low, -2.0);
  EXPECT_TRUE(std::isinf(t0.range.high));

  ASSERT_EQ(x.targets.size(), 2u);
  const Target& front = x.targets[0];
  EXPECT_EQ(front.name, "front");
  EXPECT_EQ(front.image, kData / "front.exr");
  EXPECT_FALSE(front.synthesize);
  EXPECT_EQ(front.weight, 1.0);
  EXPECT_EQ(front.gate.type, GateType::Box);
  EXPECT_EQ(front.gate.a, 2.0);
  EXPECT_FALSE(front.view.position || front.view.lookAt || front.view.up || front.view.normal);
  const Target& above = x.targets[1];
  EXPECT_EQ(above.name, "above");
  EXPECT_TRUE(above.synthesize);
  EXPECT_EQ(above.synthesizeSpp, 1024u);
  EXPECT_EQ(above.synthesizeSeed, 7u);
  EXPECT_EQ(above.weight, 0.5);
  EXPECT_EQ(above.gate.type, GateType::Bins);
  EXPECT_EQ(above.gate.binCount, 8u);
  EXPECT_EQ(above.gate.binWidth, 0.5);
  EXPECT_EQ(above.view.position, glm::vec3(0, 3, 0.5f));
  EXPECT_EQ(above.view.lookAt, glm::vec3(0, 0, 0));
  EXPECT_EQ(above.view.up, glm::vec3(0, 0, -1));
  ASSERT_EQ(above.view.lightPositions.size(), 1u);
  EXPECT_EQ(above.view.lightPositions[0].first, 0u);
  EXPECT_EQ(above.view.lightPositions[0].second, glm::vec3(0, 3, 0.5f));

  EXPECT_EQ(x.loss.type, LossType::RelativeL2);
  EXPECT_EQ(x.loss.epsilon, 0.05);
  const OptimizerSpec& o = x.optimizer;
  EXPECT_EQ(o.type, OptimizerType::Adam);
  EXPECT_EQ(o.learningRate, 0.01);
  EXPECT_EQ(o.beta1, 0.8);
  EXPECT_EQ(o.beta2, 0.99);
  EXPECT_EQ(o.epsilon, 1e-6);
  EXPECT_TRUE(o.uniform);
  using Rates = std::vector<std::pair<std::string, double>>;
  EXPECT_EQ(o.groupRates, (Rates{{"calibration", 0.001}, {"heights", 0.002}}));
  EXPECT_EQ(o.schedule.type, ScheduleType::Step);
  EXPECT_EQ(o.schedule.decay, 0.5);
  EXPECT_EQ(o.schedule.every, 50u);
  EXPECT_EQ(o.schedule.warmup, 5u);
  ASSERT_EQ(x.regularizers.size(), 1u);
  EXPECT_EQ(x.regularizers[0].shape, 0u);
  EXPECT_EQ(x.regularizers[0].weight, 0.1);
  ASSERT_TRUE(x.preconditioner);
  EXPECT_EQ(x.preconditioner->shape, 0u);
  EXPECT_EQ(x.preconditioner->lambda, 4.0);
  const BudgetSpec& b = x.budget;
  EXPECT_EQ(b.sppPrimal, 32u);
  EXPECT_EQ(b.sppInterior, 16u);
  EXPECT_EQ(b.sppEdge, 8u);
  EXPECT_EQ(b.sppBoundary, 4u);
  EXPECT_TRUE(b.interior);
  EXPECT_TRUE(b.edge);
  EXPECT_FALSE(b.pathLength);
  EXPECT_EQ(b.antithetic, "off");
  EXPECT_EQ(b.nee, NeeMode::Ellipsoidal);
  EXPECT_EQ(b.maxDepth, 6u);
  EXPECT_EQ(x.stop.iterations, 200u);
  EXPECT_EQ(x.stop.lossBelow, 1e-5);
  EXPECT_EQ(x.stop.parameterErrorBelow, 0.001);
  EXPECT_EQ(x.stop.seconds, 600.0);
  EXPECT_EQ(x.checkpointEvery, 20u);
  EXPECT_EQ(x.imagesEvery, 25u);
  EXPECT_EQ(x.seed, 42u);
}

// The examples of docs/optimize.md: the complete one is this test's data file, the minimal one parses.
TEST(Experiment, DocumentationExamplesAreValid) {
  const std::string doc = test::readAll(fs::path(VKTG_SOURCE_DIR) / "docs" / "optimize.md");
  std::vector<std::string> examples;
  for (size_t begin = doc.find("```json\n"); begin != std::string::npos; begin = doc.find("```json\n", begin + 1))
    examples.push_back(doc.substr(begin + 8, doc.find("```", begin + 8) - begin - 8));
  ASSERT_EQ(examples.size(), 2u);
  EXPECT_EQ(json::parse(examples[0]), json::parse(test::readAll(kData / "complete.json")));
  const Experiment minimal = parseExperimentJson(examples[1], "optimize.md", kData);
  EXPECT_EQ(minimal.parameters.at(0).name, "laser_y");
}

TEST(Experiment, DefaultsOfAMinimalFile) {
  const json minimal = {{"version", 1},
                        {"scene", "terrain.json"},
                        {"parameters", {{{"name", "laser_y"}}}},
                        {"targets", {{{"image", "front.exr"}}, {{"image", {{"synthesize", json::object()}}}}}}};
  expectError([&] { parseExperimentJson(minimal.dump(), kFile, kData); }, {"targets[1].image.synthesize", "truth"});
  json valid = minimal;
  valid["parameters"][0]["truth"] = 0.25;
  const Experiment x = parseExperimentJson(valid.dump(), kFile, kData);
  ASSERT_EQ(x.parameters.size(), 1u);
  EXPECT_EQ(x.parameters[0].initial, 0.0);
  EXPECT_EQ(x.parameters[0].group, "default");
  EXPECT_TRUE(std::isinf(x.parameters[0].range.low) && std::isinf(x.parameters[0].range.high));
  EXPECT_EQ(x.targets[0].name, "target_0");
  EXPECT_EQ(x.targets[1].name, "target_1");
  EXPECT_EQ(x.targets[1].synthesizeSpp, 4096u);
  EXPECT_EQ(x.targets[0].gate.type, GateType::Box);  // the scene's
  EXPECT_EQ(x.targets[1].synthesizeSeed, 0x5eedu + 1);
  EXPECT_EQ(x.loss.type, LossType::L2);
  EXPECT_EQ(x.optimizer.type, OptimizerType::Adam);
  EXPECT_EQ(x.optimizer.learningRate, 1e-2);
  EXPECT_EQ(x.optimizer.beta1, 0.9);
  EXPECT_EQ(x.optimizer.beta2, 0.999);
  EXPECT_FALSE(x.optimizer.uniform);
  EXPECT_EQ(x.optimizer.schedule.type, ScheduleType::Constant);
  EXPECT_TRUE(x.regularizers.empty());
  EXPECT_FALSE(x.preconditioner);
  EXPECT_EQ(x.budget.sppPrimal, 16u);
  EXPECT_EQ(x.budget.sppEdge, 16u);
  EXPECT_FALSE(x.budget.sppEdgeAuto || x.budget.sppBoundaryAuto || x.budget.sppBoundaryCameraAuto);
  EXPECT_TRUE(x.budget.interior && x.budget.edge && x.budget.pathLength);
  EXPECT_EQ(x.budget.antithetic, "auto");
  EXPECT_EQ(x.budget.nee, NeeMode::Auto);
  EXPECT_EQ(x.budget.maxDepth, 0u);
  EXPECT_EQ(x.stop.iterations, 100u);
  EXPECT_FALSE(x.stop.lossBelow || x.stop.parameterErrorBelow || x.stop.seconds);
  EXPECT_EQ(x.checkpointEvery, 10u);
  EXPECT_EQ(x.imagesEvery, 10u);
  EXPECT_EQ(x.seed, 0u);
}

TEST(Experiment, TermSamplesMayBeLeftToThePilot) {
  json j = baseExperiment();
  j["render"]["spp_edge"] = "auto";
  Experiment x = parseExperimentJson(j.dump(), kFile, kData);
  EXPECT_TRUE(x.budget.sppEdgeAuto);
  EXPECT_FALSE(x.budget.sppBoundaryAuto);
  j["render"]["spp_boundary"] = "auto";
  j["render"]["spp_edge"] = 3;
  x = parseExperimentJson(j.dump(), kFile, kData);
  EXPECT_FALSE(x.budget.sppEdgeAuto);
  EXPECT_EQ(x.budget.sppEdge, 3.0);
  // Fewer samples than pixels, as the pilot may choose: a fraction.
  j["render"]["spp_edge"] = 0.375;
  EXPECT_EQ(parseExperimentJson(j.dump(), kFile, kData).budget.sppEdge, 0.375);
  j["render"]["spp_edge"] = 3;
  EXPECT_TRUE(x.budget.sppBoundaryAuto);
  // The boundary's connections from the camera follow "spp_boundary" unless given their own.
  EXPECT_TRUE(x.budget.sppBoundaryCameraAuto);
  j["render"]["spp_boundary_camera"] = 5;
  x = parseExperimentJson(j.dump(), kFile, kData);
  EXPECT_TRUE(x.budget.sppBoundaryAuto);
  EXPECT_FALSE(x.budget.sppBoundaryCameraAuto);
  EXPECT_EQ(x.budget.sppBoundaryCamera, 5.0);
  j["render"]["spp_boundary"] = 7;
  j["render"].erase("spp_boundary_camera");
  x = parseExperimentJson(j.dump(), kFile, kData);
  EXPECT_FALSE(x.budget.sppBoundaryCameraAuto);
  EXPECT_EQ(x.budget.sppBoundaryCamera, 7.0);
  j["render"]["spp_boundary_camera"] = "auto";
  x = parseExperimentJson(j.dump(), kFile, kData);
  EXPECT_FALSE(x.budget.sppBoundaryAuto);
  EXPECT_TRUE(x.budget.sppBoundaryCameraAuto);
}

TEST(Experiment, PatternsSelectInSceneOrderAndEntriesKeepTheirOrder) {
  json j = baseExperiment();
  j["parameters"] = {{{"name", "grey"}, {"truth", 0}},
                     {{"name", "h1*"}, {"initial", {0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7}}, {"truth", 0}, {"group", "heights"}},
                     {{"name", "h*"}, {"truth", 0}, {"group", "heights"}, {"range", {-0.5, 0.5}}}};
  j["optimizer"]["groups"] = {{"heights", {{"learning_rate", 0.001}}}};
  // "h1*" takes h1 and h10-h15 first; "h*" then selects h0, h2 ... h9 (already-selected names are an error).
  expectError([&] { parseExperimentJson(j.dump(), kFile, kData); }, {"parameters[2].name", "\"h1\" is already selected by parameters[1]"});
  j["parameters"][2]["name"] = "h?";  // no '?' wildcard: an unknown name
  expectError([&] { parseExperimentJson(j.dump(), kFile, kData); }, {"parameters[2].name", "unknown parameter \"h?\""});
  j["parameters"].erase(2);
  const Experiment x = parseExperimentJson(j.dump(), kFile, kData);
  std::vector<std::string> names;
  for (const ExperimentParameter& p : x.parameters) names.push_back(p.name);
  EXPECT_EQ(names, (std::vector<std::string>{"grey", "h1", "h10", "h11", "h12", "h13", "h14", "h15"}));
  EXPECT_EQ(x.parameters[1].initial, 0.1);
  EXPECT_EQ(x.parameters[7].initial, 0.7);
  EXPECT_EQ(x.parameters[7].sceneIndex, 15u);
}

TEST_F(ExperimentFiles, ThousandsOfParametersAreSelectedByNameAndPattern) {
  // A 200 x 200 heightfield: 40 000 height parameters, selected by one pattern with a per-parameter
  // initial value and by 2000 exact names (a name -> index map, not a scan per name).
  const uint32_t n = 200;
  json scene = json::parse(test::readAll(kData / "terrain.json"));
  scene["shapes"][0]["resolution"] = {n, n};
  scene["shapes"][0]["heights"] = std::vector<double>(size_t(n) * n, 0.0);
  scene["parameters"] = {{{"type", "heightfield_heights"}, {"shape", "terrain"}, {"name_prefix", "h"}}};
  const fs::path dir = m_dir;
  test::writePlain(dir / "large.json", scene.dump());
  test::writePlain(dir / "front.exr", test::readAll(kData / "front.exr"));
  json j = {{"version", 1}, {"scene", "large.json"}, {"targets", {{{"image", "front.exr"}}}}};
  std::vector<double> initial(size_t(n) * n);
  for (size_t i = 0; i < initial.size(); ++i) initial[i] = double(i) * 1e-6;
  j["parameters"] = {{{"name", "h*"}, {"initial", initial}}};
  const Experiment all = parseExperimentJson(j.dump(), kFile, dir);
  ASSERT_EQ(all.parameters.size(), size_t(n) * n);
  EXPECT_EQ(all.parameters[12345].name, "h12345");
  EXPECT_EQ(all.parameters[12345].initial, 12345e-6);
  json named = json::array();
  for (size_t k = 0; k < 2000; ++k) named.push_back({{"name", "h" + std::to_string(k * 17)}});
  j["parameters"] = named;
  const Experiment some = parseExperimentJson(j.dump(), kFile, dir);
  ASSERT_EQ(some.parameters.size(), 2000u);
  EXPECT_EQ(some.parameters[1999].sceneIndex, 1999u * 17);
}

TEST(Experiment, SceneForTargetAppliesViewAndGate) {
  const Experiment x = loadExperiment(kData / "complete.json");
  const Scene front = sceneForTarget(x.scene, x.targets[0]);
  EXPECT_EQ(front.camera.position, x.scene.camera.position);
  EXPECT_EQ(front.gate.type, GateType::Box);
  const Scene above = sceneForTarget(x.scene, x.targets[1]);
  EXPECT_EQ(above.camera.position, glm::vec3(0, 3, 0.5f));
  EXPECT_EQ(above.camera.lookAt, glm::vec3(0, 0, 0));
  EXPECT_EQ(above.camera.up, glm::vec3(0, 0, -1));
  EXPECT_EQ(above.camera.width, 8u);
  EXPECT_EQ(above.pointLights[0].position, glm::vec3(0, 3, 0.5f));
  EXPECT_EQ(above.gate.type, GateType::Bins);
  EXPECT_EQ(above.gate.layers(), 8u);
  EXPECT_EQ(above.shapes[0].positions, x.scene.shapes[0].positions);
  EXPECT_EQ(x.scene.pointLights[0].position, glm::vec3(0, 2, 2));  // the experiment's scene is untouched
}

TEST(Experiment, PointSensorViewsTakePositionAndNormal) {
  json j = {{"version", 1},
            {"scene", "sensor.json"},
            {"parameters", {{{"name", "plane_y"}}}},
            {"targets", {{{"view", {{"position", {0, 2, 0}}, {"normal", {0, -2, 0}}}}, {"image", "front.exr"}}}}};
  const Experiment x = parseExperimentJson(j.dump(), kFile, kData);
  const Scene moved = sceneForTarget(x.scene, x.targets[0]);
  EXPECT_EQ(moved.camera.position, glm::vec3(0, 2, 0));
  EXPECT_EQ(moved.camera.normal, glm::vec3(0, -1, 0));
  j["targets"][0]["view"]["look_at"] = {0, 0, 0};
  expectError([&] { parseExperimentJson(j.dump(), kFile, kData); },
              {"targets[0].view.look_at", "applies to perspective cameras", "point sensor"});
  j["targets"][0]["view"] = {{"normal", {0, 0, 0}}};
  expectError([&] { parseExperimentJson(j.dump(), kFile, kData); }, {"targets[0].view.normal", "must not be zero"});
}

TEST(Experiment, ParameterErrorIsTheRmsOverKnownTruths) {
  std::vector<ExperimentParameter> parameters(3);
  parameters[0].truth = 1.0;
  parameters[2].truth = -1.0;
  EXPECT_DOUBLE_EQ(*parameterError(parameters, {4.0, 100.0, 3.0}), std::sqrt((9.0 + 16.0) / 2));
  parameters[0].truth.reset();
  parameters[2].truth.reset();
  EXPECT_FALSE(parameterError(parameters, {0, 0, 0}));
  expectError([&] { parameterError(parameters, {0}); }, {"1 values for 3 parameters"});
}

class TargetImages : public test::TempDirTest {
 protected:
  void SetUp() override {
    TempDirTest::SetUp();
    test::writePlain(m_dir / "terrain.json", test::readAll(kData / "terrain.json"));
  }

  // The base experiment with target 0's image written here first.
  Experiment withImage(const ImageSet& image) {
    writeExr(m_dir / "front.exr", image);
    return parseExperimentJson(baseExperiment().dump(), kFile, m_dir);
  }
};

ImageSet filled(uint32_t width, uint32_t height, size_t layers, float value) {
  ImageSet image{width, height, {}};
  for (size_t l = 0; l < layers; ++l)
    image.layers.push_back({layers > 1 ? "l" + std::to_string(l) : "", std::vector<float>(size_t(width) * height, value)});
  return image;
}

TEST_F(TargetImages, MatchingImageLoads) {
  const Experiment x = withImage(filled(8, 8, 1, 0.5f));
  const ImageSet image = loadTargetImage(x, 0);
  EXPECT_EQ(image.width, 8u);
  EXPECT_EQ(image.layers.at(0).pixels.at(63), 0.5f);
  expectError([&] { loadTargetImage(x, 1); }, {kFile, "targets[1].image", "target \"above\"", "synthesised"});
}

TEST_F(TargetImages, WrongSizeOrLayersAreErrors) {
  const Experiment small = withImage(filled(4, 8, 1, 0.5f));
  expectError([&] { loadTargetImage(small, 0); },
              {kFile, "targets[0].image", "target \"front\"", (m_dir / "front.exr").string(), "4x8 with 1 layer",
               "render 8x8 with 1 layer"});
  const Experiment stack = withImage(filled(8, 8, 3, 0.5f));
  expectError([&] { loadTargetImage(stack, 0); }, {"8x8 with 3 layers", "render 8x8 with 1 layer", "gate: box"});
  // A synthesised transient stack is checked the same way.
  expectError([&] { checkTargetImageSize(stack, 1, filled(8, 8, 1, 0), 8, 8, 4); },
              {"targets[1].image", "the synthesised image is 8x8 with 1 layer", "render 8x8 with 4 layers"});
  ImageSet ragged = filled(8, 8, 2, 0);
  ragged.layers[1].pixels.resize(10);
  expectError([&] { checkTargetImageSize(stack, 1, ragged, 8, 8, 2); }, {"layer \"l1\" holds 10 pixels, not 64"});
}

TEST_F(TargetImages, NonFinitePixelsAreErrors) {
  ImageSet image = filled(8, 8, 1, 0.5f);
  image.layers[0].pixels[8 * 3 + 2] = NAN;
  image.layers[0].pixels[60] = INFINITY;
  const Experiment x = withImage(image);
  expectError([&] { loadTargetImage(x, 0); }, {"targets[0].image", "2 non-finite pixel(s)", "nan at x 2, y 3"});
  expectError([&] { checkTargetImageFinite(x, 1, filled(2, 2, 2, -INFINITY)); },
              {"targets[1].image", "the synthesised image holds 8 non-finite", "of layer \"l0\""});
}

TEST_F(TargetImages, UnreadableExrNamesTheFieldAndTheFile) {
  const Experiment x = withImage(filled(8, 8, 1, 0.5f));
  test::writePlain(m_dir / "front.exr", "not an EXR file");
  expectError([&] { loadTargetImage(x, 0); }, {kFile, "targets[0].image", (m_dir / "front.exr").string()});
}

// A scan target: sensor.json's point sensor and laser over a 3 x 2 grid, the cube written beside it.
class ScanTargets : public test::TempDirTest {
 protected:
  void SetUp() override {
    TempDirTest::SetUp();
    test::writePlain(m_dir / "sensor.json", test::readAll(kData / "sensor.json"));
    test::writePlain(m_dir / "scan.json", R"({"version": 1, "grid": {"corner": [-1, 1, -1], "across": [2, 0, 0],
        "down": [0, 0, 1], "resolution": [3, 2], "lights": ["laser"]}})");
  }
  json experiment(const json& image) const {
    return {{"version", 1},
            {"scene", "sensor.json"},
            {"parameters", {{{"name", "plane_y"}, {"truth", 0}}}},
            {"targets", {{{"name", "wall"}, {"scan", "scan.json"}, {"gate", {{"spec", "bins:1.5,0.5,4"}}}, {"image", image}},
                         {{"name", "single"}, {"image", {{"synthesize", json::object()}}}}}}};
  }
};

TEST_F(ScanTargets, AScanIsOneTargetPerPointNamedByColumnAndRow) {
  const Experiment x = parseExperimentJson(experiment({{"synthesize", {{"spp", 16}}}}).dump(), kFile, m_dir);
  ASSERT_EQ(x.targets.size(), 7u);
  for (uint32_t k = 0; k < 6; ++k) {
    const Target& t = x.targets[k];
    EXPECT_EQ(t.name, "wall_" + std::to_string(k % 3) + "_" + std::to_string(k / 3));
    EXPECT_EQ(t.entry, 0u);
    EXPECT_EQ(t.scanView, k);
    EXPECT_EQ(t.gate.layers(), 4u);
    const glm::vec3 point(-1.0f + float(k % 3), 1.0f, -1.0f + float(k / 3));
    EXPECT_EQ(sceneForTarget(x.scene, t).camera.position, point);
    EXPECT_EQ(sceneForTarget(x.scene, t).pointLights[0].position, point) << "the laser follows the sensor";
    EXPECT_EQ(t.synthesizeSeed, 0x5eedu + k) << "the seeds a target per point would get";
  }
  EXPECT_EQ(x.targets[6].entry, 1u);
  EXPECT_FALSE(x.targets[6].scanView);
  EXPECT_EQ(x.targets[6].synthesizeSeed, 0x5eedu + 6);
}

TEST_F(ScanTargets, EachPointReadsItsPixelOfTheScanImage) {
  // Pixel (i, j), bin b holds 100 j + 10 i + b.
  ImageSet cube{3, 2, {}};
  for (uint32_t b = 0; b < 4; ++b) {
    cube.layers.push_back({"bin" + std::to_string(b), {}});
    for (uint32_t j = 0; j < 2; ++j)
      for (uint32_t i = 0; i < 3; ++i) cube.layers[b].pixels.push_back(float(100 * j + 10 * i + b));
  }
  writeExr(m_dir / "cube.exr", cube);
  const Experiment x = parseExperimentJson(experiment("cube.exr").dump(), kFile, m_dir);
  for (uint32_t k = 0; k < 6; ++k) {
    const ImageSet point = loadTargetImage(x, k);
    ASSERT_EQ(point.width * point.height, 1u);
    ASSERT_EQ(point.layers.size(), 4u);
    for (uint32_t b = 0; b < 4; ++b) EXPECT_EQ(point.layers[b].pixels[0], float(100 * (k / 3) + 10 * (k % 3) + b));
  }
  writeExr(m_dir / "cube.exr", filled(2, 3, 4, 1.0f));
  expectError([&] { loadTargetImage(x, 4); },
              {kFile, "targets[0].image", "target \"wall_1_1\"", "2x3 with 4 layers", "scan of 6 views",
               "render 3x2 with 4 layers"});
}

// The log and the initial images go by "targets" entry: a scan's points are one entry, whose images
// join into the cube they were read from and split back into the same points.
TEST_F(ScanTargets, AScanIsOneEntryWhoseImagesJoinIntoItsCube) {
  ImageSet cube{3, 2, {}};
  for (uint32_t b = 0; b < 4; ++b) {
    cube.layers.push_back({"bin" + std::to_string(b), {}});
    for (uint32_t p = 0; p < 6; ++p) cube.layers[b].pixels.push_back(float(10 * p + b));
  }
  writeExr(m_dir / "cube.exr", cube);
  const Experiment x = parseExperimentJson(experiment("cube.exr").dump(), kFile, m_dir);
  const std::vector<TargetEntry> entries = targetEntries(x);
  ASSERT_EQ(entries.size(), 2u);
  EXPECT_EQ(entries[0].name, "wall");
  EXPECT_TRUE(entries[0].scan);
  EXPECT_EQ(entries[0].targets, (std::vector<size_t>{0, 1, 2, 3, 4, 5}));
  EXPECT_EQ(entries[1].name, "single");
  EXPECT_FALSE(entries[1].scan);
  EXPECT_EQ(entries[1].targets, std::vector<size_t>{6});
  std::vector<ImageSet> points;
  for (size_t t = 0; t < 6; ++t) points.push_back(loadTargetImage(x, t));
  points.push_back(filled(1, 1, 4, 0.0f));
  const ImageSet joined = joinScanImages(x, entries[0], points);
  EXPECT_EQ(joined.width, 3u);
  EXPECT_EQ(joined.height, 2u);
  ASSERT_EQ(joined.layers.size(), 4u);
  for (uint32_t b = 0; b < 4; ++b) EXPECT_EQ(joined.layers[b].pixels, cube.layers[b].pixels) << "bin " << b;
  const std::vector<ImageSet> split = splitScanImage(x, entries[0], joined, "initial.exr");
  ASSERT_EQ(split.size(), 6u);
  for (size_t t = 0; t < 6; ++t)
    for (uint32_t b = 0; b < 4; ++b) EXPECT_EQ(split[t].layers[b].pixels, points[t].layers[b].pixels) << t << ", bin " << b;
  expectError([&] { splitScanImage(x, entries[0], filled(2, 3, 4, 1.0f), "initial.exr"); },
              {"initial.exr", "2x3 with 4 layers", "scan \"wall\"", "3x2 with 4 layers"});
}

TEST_F(ScanTargets, Errors) {
  json j = experiment("cube.exr");
  writeExr(m_dir / "cube.exr", filled(3, 2, 4, 1.0f));
  j["targets"][0]["view"] = {{"position", {0, 1, 0}}};
  expectError([&] { parseExperimentJson(j.dump(), kFile, m_dir); }, {"targets[0].scan", "a view or a scan, not both"});
  j = experiment("cube.exr");
  j["targets"][0]["scan"] = "absent.json";
  expectError([&] { parseExperimentJson(j.dump(), kFile, m_dir); }, {"absent.json"});
  test::writePlain(m_dir / "scan.json", R"({"version": 1, "grid": {"corner": [0, 1, 0], "resolution": [2, 1]}})");
  expectError([&] { parseExperimentJson(experiment("cube.exr").dump(), kFile, m_dir); },
              {(m_dir / "scan.json").string(), "grid.across", "non-zero"});
  test::writePlain(m_dir / "scan.json", R"({"version": 1, "views": [{"position": [0, 1, 0]}, {"position": [0, 1, 0]}]})");
  j = experiment("cube.exr");
  j["targets"][1]["name"] = "wall_1";
  expectError([&] { parseExperimentJson(j.dump(), kFile, m_dir); }, {"targets[1].name", "duplicate target name \"wall_1\""});
  // A file that is no EXR is named with its own entry's field, not its position among the targets.
  writeExr(m_dir / "cube.exr", filled(3, 2, 4, 1.0f));
  test::writePlain(m_dir / "scan.json", R"({"version": 1, "grid": {"corner": [-1, 1, -1], "across": [2, 0, 0],
      "down": [0, 0, 1], "resolution": [3, 2], "lights": ["laser"]}})");
  test::writePlain(m_dir / "broken.exr", "not an EXR");
  j = experiment("cube.exr");
  j["targets"][1]["image"] = "broken.exr";
  const Experiment broken = parseExperimentJson(j.dump(), kFile, m_dir);
  expectError([&] { loadTargetImage(broken, 6); }, {kFile, "targets[1].image", "broken.exr"});
  // A scan's name is its log column's and initial image's, so no other target may take it.
  j["targets"][1]["name"] = "wall";
  expectError([&] { parseExperimentJson(j.dump(), kFile, m_dir); }, {"targets[1].name", "duplicate target name \"wall\""});
}

TEST_F(ExperimentFiles, MissingExperimentFile) {
  const fs::path missing = kData / "absent.json";
  expectError([&] { loadExperiment(missing); }, {missing.string(), "file not found"});
}

}  // namespace
}  // namespace vktg
