// Scene parameters: named scalars θ_k, each 0 at the scene as written, bound to one scene quantity
// (THEORY.md §2-3, DESIGN.md §2 "Parameters"). Geometric parameters become per-vertex velocity
// fields dV/dθ_k, which is all the derivative passes see; the others name the one scalar they add to.
// vktg/scene.h includes this header (Scene holds its parameters), so include vktg/scene.h to call
// the functions below.
#pragma once
#include <cmath>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

namespace vktg {

struct Scene;

// Units of θ for each kind (what one unit of θ changes):
enum class ParameterKind : uint32_t {
  Translate = 0,      // a shape moves rigidly along `axis`: metres
  Rotate = 1,         // a shape turns about `axis` through `center` (right-handed): radians
  Displace = 2,       // chosen vertices of a shape move by `axis` per unit θ (metres along a unit direction,
                      // or for heightfield heights, the world image of one unit of the file's height)
  LightPosition = 3,  // a point light moves along `axis`: metres
  Emission = 4,       // a shape's emitted radiance is added to: W sr^-1 m^-2
  Intensity = 5,      // a point light's intensity is added to: W sr^-1
  Albedo = 6,         // a material's albedo is added to (dimensionless)
  Roughness = 7,      // a material's GGX alpha is added to (dimensionless)
  Ior = 8,            // a material's index of refraction is added to (dimensionless)
  GateCenter = 9,     // the whole gate shifts to longer path lengths: W_θ(L) = W(L - θ), metres
};

struct Parameter {
  std::string name;
  ParameterKind kind = ParameterKind::Translate;
  std::string target;                  // shape, point light or material name; empty for GateCenter
  glm::vec3 axis{0.0f};                // Translate, Rotate, LightPosition: unit axis; Displace: see above
  glm::vec3 center{0.0f};              // Rotate: a point on the rotation axis (world space)
  std::vector<uint32_t> vertices;      // Displace: indices into the shape's positions, distinct
};

// Parameter names are non-empty and use only letters, digits, '_', '-' and '.', so command-line
// lists ("a,b") and wildcards ("h*") can name them unambiguously.
bool isValidParameterName(const std::string& name);

// Scene-file entries that expand to one Displace parameter per vertex and direction, named
// <prefix><vertex><suffix> and ordered by vertex, then direction: "heightfield_heights" (suffix "",
// along the heightfield's up; default prefix "<shape>_h") and "vertex_positions" (suffixes "_x",
// "_y", "_z", along the world axes; default prefix "<shape>_v"). Other types: no suffixes.
struct VertexExpansion {
  std::vector<std::string> suffixes;
  std::string defaultPrefix;
};
VertexExpansion vertexExpansion(const std::string& type, const std::string& shape);

// Moves vertices or a point light: needs velocity fields and may move occluders (edge terms).
bool isGeometric(ParameterKind kind);
bool isGeometric(const Parameter& parameter);
// Moves vertices of a shape (Translate, Rotate, Displace): ParameterBinding::vertexVelocity is filled.
bool movesVertices(ParameterKind kind);
// The name used in scene files: "translate", "rotate", "displace", "light_position", "emission",
// "intensity", "albedo", "roughness", "ior", "gate_center".
const char* parameterKindName(ParameterKind kind);

// Why `parameter` cannot be differentiated in `scene`, or "" if it can: its target does not exist
// or has the wrong kind, or its derivative is identically zero or invisible to the renderer (the
// albedo of a material no shape uses, the roughness of a diffuse material, the ior of a
// non-dielectric, the emission of a shape that does not emit, the intensity of a dark light, the
// centre of a steady gate, a zero axis, a vertex index out of range, an empty vertex list).
// The scene parser reports this problem against the offending field.
std::string parameterProblem(const Scene& scene, const Parameter& parameter);

// The scene with parameter `name` moved by `delta` (θ = delta), for finite differences. Positions
// are computed in double precision and rounded once. Throws vktg::Error for an unknown name and when
// the moved value leaves the range the scene format accepts (albedo in [0, 1], roughness in
// [0.001, 1], ior > 1, emission and intensity > 0 so the emitter stays a light, a valid gate):
// beyond it the renderer clamps or drops the value and the difference quotient would be wrong.
Scene perturbScene(const Scene& scene, const std::string& name, double delta);

// The scene with several parameters set at once: (index in Scene::parameters, θ) pairs, applied in
// the order the scene declares the parameters (a rotation and a translation of one shape do not
// commute). Scalars add up when several parameters target one; range errors as for perturbScene.
Scene applyParameters(const Scene& scene, const std::vector<std::pair<uint32_t, double>>& values);

// Moves `scene` in place by one parameter at θ (what applyParameters does for each entry).
void applyParameter(Scene& scene, const Parameter& parameter, double theta);

// The motion of one vertex under a Translate, Rotate or Displace parameter at θ (Displace moves only
// the vertices it lists: the caller decides which), and how the same motion turns a direction.
glm::dvec3 moveVertex(const Parameter& parameter, const glm::dvec3& position, double theta);
glm::dvec3 turnVector(const Parameter& parameter, const glm::dvec3& vector, double theta);

// The values θ may take so that the scene stays inside what the scene format accepts (the ranges
// perturbScene enforces): albedo in [0, 1], roughness in [0.001, 1], ior > 1, emission and intensity
// > 0, a gate with a, mu, start >= 0; geometric parameters are unbounded. `lowOpen`/`highOpen` say
// whether an end is excluded (then a projection must stay strictly inside).
struct ParameterRange {
  double low = -INFINITY, high = INFINITY;
  bool lowOpen = false, highOpen = false;
  bool contains(double theta) const {
    return (lowOpen ? theta > low : theta >= low) && (highOpen ? theta < high : theta <= high);
  }
};
ParameterRange parameterRange(const Scene& scene, const Parameter& parameter);

// What one selected parameter touches, in the form the renderer uploads.
struct ParameterBinding {
  std::string name;
  ParameterKind kind = ParameterKind::Translate;
  uint32_t parameter = 0;  // index into Scene::parameters
  // Index of what it touches: Scene::shapes (Translate, Rotate, Displace, Emission),
  // Scene::pointLights (LightPosition, Intensity), Scene::materials (Albedo, Roughness, Ior); 0 for GateCenter.
  uint32_t target = 0;
  // dV/dθ (metres per unit θ) for every vertex of the scene, shapes concatenated in order as
  // prepareScene concatenates them; zero off the moving shape. Empty unless movesVertices(kind).
  std::vector<glm::vec3> vertexVelocity;
  glm::vec3 lightVelocity{0.0f};  // LightPosition: dP/dθ of the light (metres per unit θ)
};

// Binds the named parameters, in the order given. Throws vktg::Error for an unknown name.
std::vector<ParameterBinding> bindParameters(const Scene& scene, const std::vector<std::string>& names);

// Parses a command-line list "a,b,c" (--param). An item containing '*' is a wildcard ("h*" matches
// h0, h1, ... in scene order) and must match at least one parameter. The result keeps the order
// of the list, each name once. Throws vktg::Error naming `field`, with close matches for an
// unknown name.
std::vector<std::string> selectParameters(const Scene& scene, const std::string& list,
                                          const std::string& field = "--param");

// " (did you mean: a, b)" listing parameters whose names are close to `name` (or " (the scene
// defines: ...)" when none is), for error messages about an unknown name.
std::string parameterSuggestions(const Scene& scene, const std::string& name);

// Whether `name` matches `pattern`, in which '*' matches any run of characters (including none)
// and everything else matches itself.
bool matchesWildcard(const std::string& pattern, const std::string& name);

// The index in Scene::parameters of `name`; throws vktg::Error (naming `field`, listing close
// matches) if there is none.
uint32_t findParameter(const Scene& scene, const std::string& name, const std::string& field = "--param");

}  // namespace vktg
