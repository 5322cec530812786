#include "scene/mitsuba_plugin.h"

#include <algorithm>
#include <charconv>
#include <numeric>

#include "scene/mitsuba_values.h"

namespace vktg {
namespace {

constexpr std::string_view kPropertyTags[] = {"float", "integer", "boolean", "string", "rgb",
                                              "spectrum", "point", "vector", "transform"};
constexpr std::string_view kObjectTags[] = {"bsdf", "emitter", "film", "sampler", "rfilter", "sensor",
                                            "shape", "integrator", "texture", "medium", "phase", "volume"};

bool isIn(std::string_view tag, const auto& list) { return std::find(std::begin(list), std::end(list), tag) != std::end(list); }

// A <spectrum type="..."> is a texture plugin, as in Mitsuba.
bool isObject(const XmlNode& node) { return isIn(node.tag, kObjectTags) || (node.tag == "spectrum" && node.attribute("type")); }

void checkAttributes(const XmlDocument& document, const XmlNode& node, std::initializer_list<std::string_view> required,
                     std::initializer_list<std::string_view> optional) {
  for (const auto& [key, value] : node.attributes)
    if (std::find(required.begin(), required.end(), key) == required.end() &&
        std::find(optional.begin(), optional.end(), key) == optional.end())
      document.fail(node, "unexpected attribute " + quote(key));
  for (std::string_view key : required)
    if (!node.attribute(key)) document.fail(node, "missing required attribute " + quote(key));
}

void checkPropertyAttributes(const XmlDocument& document, const XmlNode& node) {
  if (node.tag == "point" || node.tag == "vector")
    checkAttributes(document, node, {"name"}, {"value", "x", "y", "z"});
  else if (node.tag == "spectrum")
    checkAttributes(document, node, {"name"}, {"value", "filename"});
  else if (node.tag == "transform")
    checkAttributes(document, node, {"name"}, {});
  else
    checkAttributes(document, node, {"name", "value"}, {});
}

// Mitsuba's spectrum text: one number (a constant spectrum), or "wavelength:value" pairs.
std::vector<double> spectrumValues(const XmlDocument& document, const XmlNode& node, const std::string& text) {
  const std::vector<std::string> words = splitValueList(text);
  if (words.size() == 1 && words.front().find(':') == std::string::npos) {
    const std::optional<double> v = parseFiniteNumber(words.front());
    if (!v) document.fail(node, "value: " + quote(words.front()) + " is not a finite number");
    return {*v};
  }
  if (words.empty()) document.fail(node, "an empty spectrum");
  std::vector<double> values;
  double previous = 0;
  for (const std::string& word : words) {
    const size_t colon = word.find(':');
    const std::optional<double> wavelength = colon == std::string::npos ? std::nullopt : parseFiniteNumber(word.substr(0, colon));
    const std::optional<double> value = colon == std::string::npos ? std::nullopt : parseFiniteNumber(word.substr(colon + 1));
    if (!wavelength || !value)
      document.fail(node, "value: " + quote(word) + " is not wavelength:value (a spectrum lists pairs like \"400:0.5, 700:0.8\")");
    if (*wavelength <= previous) document.fail(node, "value: the wavelengths must increase");
    previous = *wavelength;
    values.push_back(*value);
  }
  return values;
}

}  // namespace

double XmlColor::mean() const {
  return std::accumulate(channels.begin(), channels.end(), 0.0) / double(channels.size());
}

PluginElement::PluginElement(const XmlDocument& document, const XmlNode& node) : m_document(&document), m_node(&node) {
  if (node.tag == "scene") {
    checkAttributes(document, node, {}, {"version", "id", "name"});
  } else {
    checkAttributes(document, node, {"type"}, {"id", "name"});
    m_type = *node.attribute("type");
  }
  for (const XmlNode& child : node.children) {
    if (isObject(child)) {
      if (child.tag == "spectrum")
        document.fail(child, "spectrum plugins (textures) are not supported: give the spectrum's values");
      const std::string* name = child.attribute("name");
      m_objects.push_back({&child, &child, name ? *name : ""});
    } else if (isIn(child.tag, kPropertyTags)) {
      checkPropertyAttributes(document, child);
      if (child.tag != "transform" && !child.children.empty())
        document.fail(child.children.front(), "a property element holds no elements");
      const std::string& name = *child.attribute("name");
      if (find(name)) document.fail(child, "property " + quote(name) + " given twice");
      m_properties.push_back({&child});
    } else if (child.tag == "ref") {
      checkAttributes(document, child, {"id"}, {"name"});
      if (!child.children.empty()) document.fail(child.children.front(), "a <ref> holds no elements");
      const std::string& id = *child.attribute("id");
      const XmlNode* target = document.findId(id);
      if (!target) document.fail(child, "no element has id " + quote(id));
      const std::string* name = child.attribute("name");
      m_objects.push_back({target, &child, name ? *name : ""});
    } else if (child.tag == "translate" || child.tag == "rotate" || child.tag == "scale" || child.tag == "lookat" ||
               child.tag == "matrix") {
      document.fail(child, "a transform operation belongs inside a <transform name=\"to_world\">");
    } else if (child.tag == "alias" || child.tag == "path") {
      document.fail(child, "<" + child.tag + "> is not supported (file names resolve against the scene file's folder)");
    } else {
      document.fail(child, "unknown element <" + child.tag + ">");
    }
  }
}

std::string PluginElement::id() const {
  const std::string* id = m_node->attribute("id");
  return id ? *id : "";
}

PluginElement::Property* PluginElement::find(std::string_view name) {
  for (Property& p : m_properties)
    if (*p.node->attribute("name") == name) return &p;
  return nullptr;
}

bool PluginElement::has(std::string_view name) const {
  return std::any_of(m_properties.begin(), m_properties.end(),
                     [&](const Property& p) { return *p.node->attribute("name") == name; });
}

const XmlNode& PluginElement::propertyNode(std::string_view name) const {
  for (const Property& p : m_properties)
    if (*p.node->attribute("name") == name) return *p.node;
  fail("no property " + quote(name));
}

const XmlNode* PluginElement::take(std::string_view name, std::initializer_list<std::string_view> kinds) {
  m_asked.emplace(name);
  Property* p = find(name);
  if (!p) return nullptr;
  p->taken = true;
  if (std::find(kinds.begin(), kinds.end(), p->node->tag) == kinds.end()) {
    std::string expected;
    for (std::string_view k : kinds) expected += (expected.empty() ? "<" : " or <") + std::string(k) + ">";
    m_document->fail(*p->node, "property " + quote(name) + " of " + XmlDocument::describe(*m_node) + " is a " + expected);
  }
  return p->node;
}

std::optional<double> PluginElement::number(std::string_view name) {
  const XmlNode* node = take(name, {"float", "integer"});
  if (!node) return std::nullopt;
  return numberAttribute(*m_document, *node, "value");
}

std::optional<int64_t> PluginElement::integer(std::string_view name) {
  const XmlNode* node = take(name, {"integer"});
  if (!node) return std::nullopt;
  const std::vector<std::string> words = splitValueList(*node->attribute("value"));
  int64_t value = 0;
  if (words.size() == 1) {
    const std::string& w = words.front();
    const auto [end, error] = std::from_chars(w.data(), w.data() + w.size(), value);
    if (error == std::errc() && end == w.data() + w.size()) return value;
  }
  m_document->fail(*node, "value: " + quote(*node->attribute("value")) + " is not an integer");
}

std::optional<bool> PluginElement::boolean(std::string_view name) {
  const XmlNode* node = take(name, {"boolean"});
  if (!node) return std::nullopt;
  std::string text = *node->attribute("value");
  std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  if (text == "true") return true;
  if (text == "false") return false;
  m_document->fail(*node, "value: " + quote(*node->attribute("value")) + " is not true or false");
}

std::optional<std::string> PluginElement::string(std::string_view name) {
  const XmlNode* node = take(name, {"string"});
  if (!node) return std::nullopt;
  return *node->attribute("value");
}

std::optional<glm::dvec3> PluginElement::point(std::string_view name) {
  const XmlNode* node = take(name, {"point", "vector"});
  if (!node) return std::nullopt;
  if (node->attribute("value")) {
    if (node->attribute("x") || node->attribute("y") || node->attribute("z"))
      m_document->fail(*node, "give either value or x, y, z, not both");
    const std::vector<std::string> words = splitValueList(*node->attribute("value"));
    if (words.size() == 1) return glm::dvec3(numberAttribute(*m_document, *node, "value"));
    return vectorAttribute(*m_document, *node, "value");
  }
  return glm::dvec3(numberAttribute(*m_document, *node, "x"), numberAttribute(*m_document, *node, "y"),
                    numberAttribute(*m_document, *node, "z"));
}

std::optional<glm::dmat4> PluginElement::transform(std::string_view name) {
  const XmlNode* node = take(name, {"transform"});
  if (!node) return std::nullopt;
  return parseTransform(*m_document, *node);
}

std::optional<XmlColor> PluginElement::color(std::string_view name) {
  for (Object& o : m_objects)
    if (o.name == name) {
      o.taken = true;
      m_document->fail(*o.site, "textures are not supported: give " + quote(name) +
                                    " as an <rgb>, a <spectrum value=\"...\"> or a <float>");
    }
  const XmlNode* node = take(name, {"rgb", "spectrum", "float", "integer"});
  if (!node) return std::nullopt;
  XmlColor color;
  color.node = node;
  if (node->tag == "float" || node->tag == "integer") {
    color.channels = {numberAttribute(*m_document, *node, "value")};
  } else if (node->tag == "rgb") {
    const std::vector<std::string> words = splitValueList(*node->attribute("value"));
    if (words.size() != 1 && words.size() != 3)
      m_document->fail(*node, "an <rgb> holds 1 or 3 numbers, not " + std::to_string(words.size()));
    for (const std::string& word : words) {
      const std::optional<double> v = parseFiniteNumber(word);
      if (!v) m_document->fail(*node, "value: " + quote(word) + " is not a finite number");
      color.channels.push_back(*v);
    }
  } else {
    if (node->attribute("filename"))
      m_document->fail(*node, "spectrum files are not supported: list the spectrum's values");
    if (!node->attribute("value")) m_document->fail(*node, "missing required attribute \"value\"");
    color.channels = spectrumValues(*m_document, *node, *node->attribute("value"));
  }
  return color;
}

std::vector<const XmlNode*> PluginElement::objects(std::string_view tag) {
  std::vector<const XmlNode*> out;
  for (Object& o : m_objects)
    if (o.target->tag == tag) {
      o.taken = true;
      out.push_back(o.target);
    }
  return out;
}

void PluginElement::finish() const {
  std::string reads;
  for (const std::string& name : m_asked) reads += (reads.empty() ? "" : ", ") + name;
  const std::string what = XmlDocument::describe(*m_node);
  for (const Property& p : m_properties)
    if (!p.taken)
      m_document->fail(*p.node, "not a property vktg reads for " + what +
                                    (reads.empty() ? " (it takes none)" : " (it reads " + reads + ")"));
  for (const Object& o : m_objects)
    if (!o.taken) {
      std::string problem = "vktg does not read a nested <" + o.target->tag + "> in " + what;
      if (o.site != o.target) problem = "refers to " + XmlDocument::describe(*o.target) + ": " + problem;
      m_document->fail(*o.site, problem);
    }
}

}  // namespace vktg
