// One plugin element of a Mitsuba scene (<bsdf type="diffuse">, <shape type="obj">, <scene>): its
// properties by name and its nested objects (a <ref id="..."/> stands for the element it names),
// each taken at most once by the code that maps the plugin. finish() fails on whatever was not
// taken, so nothing a file says is silently dropped.
#pragma once
#include <cstdint>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>

#include "scene/mitsuba_xml_document.h"

namespace vktg {

// A colour-like value (<rgb>, <spectrum value="...">, <float>): the numbers it holds (one, or r, g,
// b, or a spectrum's samples) and where it was written.
struct XmlColor {
  std::vector<double> channels;
  const XmlNode* node = nullptr;
  // vktg's monochromatic value: the mean of the channels (docs/scene-format.md, "Mitsuba 3 XML").
  double mean() const;
};

class PluginElement {
 public:
  // Checks the element's attributes (type, id, name) and its children: property elements with a
  // name and the attributes their kind takes, nested objects, refs to an existing id.
  PluginElement(const XmlDocument& document, const XmlNode& node);

  const XmlDocument& document() const { return *m_document; }
  const XmlNode& node() const { return *m_node; }
  const std::string& type() const { return m_type; }
  std::string id() const;  // "" without one
  [[noreturn]] void fail(const std::string& problem) const { m_document->fail(*m_node, problem); }

  // Whether the element has a property of this name (read or not).
  bool has(std::string_view name) const;
  // The property element of that name; it must exist.
  const XmlNode& propertyNode(std::string_view name) const;

  // Typed reads: nothing when the property is absent; a property of another kind fails.
  std::optional<double> number(std::string_view name);     // <float> or <integer>
  std::optional<int64_t> integer(std::string_view name);   // <integer>
  std::optional<bool> boolean(std::string_view name);      // <boolean>
  std::optional<std::string> string(std::string_view name);  // <string>
  std::optional<glm::dvec3> point(std::string_view name);  // <point> or <vector>
  std::optional<glm::dmat4> transform(std::string_view name);  // <transform>
  // <rgb>, <spectrum value=...>, <float> or <integer>. A texture (an object of this name, or a ref
  // to one) fails: vktg reads no textures.
  std::optional<XmlColor> color(std::string_view name);

  // Takes every nested object with this tag (refs resolved to their targets), in document order.
  std::vector<const XmlNode*> objects(std::string_view tag);
  // Fails on any property or nested object not taken, naming what this plugin reads.
  void finish() const;

 private:
  struct Property {
    const XmlNode* node;
    bool taken = false;
  };
  struct Object {
    const XmlNode* target;  // the object (a ref's target)
    const XmlNode* site;    // where it appears here: the object itself or the <ref>
    std::string name;       // its name attribute (the property it binds to), "" without one
    bool taken = false;
  };
  Property* find(std::string_view name);
  const XmlNode* take(std::string_view name, std::initializer_list<std::string_view> kinds);

  const XmlDocument* m_document;
  const XmlNode* m_node;
  std::string m_type;
  std::vector<Property> m_properties;
  std::vector<Object> m_objects;
  std::set<std::string, std::less<>> m_asked;  // names the mapping asked for, for the error message
};

}  // namespace vktg
