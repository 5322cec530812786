#include "scene/mitsuba_xml_document.h"

#include <algorithm>
#include <cctype>
#include <system_error>

#include <pugixml.hpp>

#include "scene/scene_values.h"
#include "vktg/error.h"

namespace vktg {

namespace fs = std::filesystem;

namespace {

// Bounds that keep a hostile file from exhausting the stack or the memory: far above any scene.
constexpr size_t kMaxIncludeDepth = 16;
constexpr size_t kMaxNesting = 64;
constexpr size_t kMaxElements = size_t(1) << 20;
constexpr size_t kMaxAttributeLength = size_t(1) << 20;

// "2.1.0", "3.0" or "3": up to three dot-separated integers; the first is the major version.
bool parseVersion(const std::string& text, int& major) {
  size_t parts = 0, start = 0;
  while (true) {
    size_t end = text.find('.', start);
    const std::string part = text.substr(start, end == std::string::npos ? std::string::npos : end - start);
    if (part.empty() || part.size() > 6 || !std::all_of(part.begin(), part.end(), [](unsigned char c) { return std::isdigit(c); }))
      return false;
    if (parts++ == 0) major = std::stoi(part);
    if (end == std::string::npos) break;
    start = end + 1;
  }
  return parts <= 3;
}

// The line of the byte at `offset`: 1 plus the line feeds before it (pugixml reports offsets).
size_t lineNumberAt(std::string_view text, size_t offset) {
  return 1 + size_t(std::count(text.begin(), text.begin() + std::min(offset, text.size()), '\n'));
}

}  // namespace

bool isValidDefineName(std::string_view name) {
  return !name.empty() &&
         std::all_of(name.begin(), name.end(), [](unsigned char c) { return std::isalnum(c) || c == '_'; });
}

const std::string* XmlNode::attribute(std::string_view name) const {
  for (const auto& [key, value] : attributes)
    if (key == name) return &value;
  return nullptr;
}

std::string XmlDocument::location(const XmlNode& node) const {
  const File& file = m_files.at(node.file);
  return file.path.string() + ":" + std::to_string(lineNumberAt(file.text, node.offset));
}

std::string XmlDocument::describe(const XmlNode& node) {
  std::string text = "<" + node.tag;
  for (const char* key : {"type", "id", "name"})
    if (const std::string* value = node.attribute(key)) text += std::string(" ") + key + "=\"" + *value + "\"";
  return text + ">";
}

void XmlDocument::fail(const XmlNode& node, const std::string& problem) const {
  throw Error(location(node) + ": " + describe(node) + ": " + problem);
}

const XmlNode* XmlDocument::findId(std::string_view id) const {
  const auto it = m_ids.find(id);
  return it == m_ids.end() ? nullptr : it->second;
}

std::vector<std::string> XmlDocument::ids() const {
  std::vector<std::string> out;
  for (const auto& [id, node] : m_ids) out.push_back(id);
  return out;
}

// Builds an XmlDocument: reads files, follows includes, applies defaults and substitutions, in
// document order, as Mitsuba's parser does (a $name is replaced by the value known when its element
// is read, so a <default> must come before the elements that use it).
class XmlExpander {
 public:
  XmlExpander(XmlDocument& document, const SceneDefines& defines) : m_document(document) {
    for (const auto& [name, value] : defines) m_parameters.push_back({name, value, true, false});
    sortParameters();
  }

  void run(const fs::path& path) {
    for (const Parameter& p : m_parameters)
      if (!isValidDefineName(p.name))
        vktg::fail(path.string(), "-D " + p.name,
                   "not a parameter name: a $name in a Mitsuba scene uses only letters, digits and '_'");
    const uint32_t file = readFile(path, nullptr);
    pugi::xml_document doc;
    const pugi::xml_node root = parse(file, doc, nullptr);
    XmlNode scene = startNode(root, file);
    if (scene.tag != "scene")
      m_document.fail(scene, "the root element of a scene file must be <scene version=\"...\">");
    for (const auto& [key, value] : scene.attributes)
      if (key != "version" && key != "id" && key != "name")
        m_document.fail(scene, "unexpected attribute \"" + key + "\" (a <scene> takes version, id and name)");
    m_includeStack.push_back(canonical(path));
    convertChildren(root, file, scene.children, 1);
    m_document.m_root = std::make_unique<XmlNode>(std::move(scene));
    for (const Parameter& p : m_parameters)
      if (p.fromDefine && !p.used)
        vktg::fail(path.string(), "-D " + p.name, "the scene uses no $" + p.name + " (no attribute names it)");
    indexIds(*m_document.m_root);
  }

 private:
  struct Parameter {
    std::string name;
    std::string value;
    bool fromDefine;  // -D on the command line: must be used
    bool used;
  };

  // Longest first, so that $ab is replaced before $a could take its prefix (Mitsuba's order).
  void sortParameters() {
    std::stable_sort(m_parameters.begin(), m_parameters.end(),
                     [](const Parameter& a, const Parameter& b) { return a.name.size() > b.name.size(); });
  }

  static fs::path canonical(const fs::path& path) {
    std::error_code ignored;
    const fs::path resolved = fs::weakly_canonical(path, ignored);
    return resolved.empty() ? path.lexically_normal() : resolved;
  }

  // Reads a file's bytes; `site` is the <include> that names it (nullptr for the scene file).
  uint32_t readFile(const fs::path& path, const XmlNode* site) {
    std::string text;
    try {
      text = readTextFile(path);
    } catch (const Error& e) {
      if (!site) throw;
      m_document.fail(*site, e.what());
    }
    m_document.m_files.push_back({path, std::move(text)});
    return uint32_t(m_document.m_files.size() - 1);
  }

  // Parses file `file` and returns its root element, which must carry a version Mitsuba 2 or 3 reads.
  pugi::xml_node parse(uint32_t file, pugi::xml_document& doc, const XmlNode* site) {
    const std::string& text = m_document.m_files[file].text;
    const std::string name = m_document.m_files[file].path.string();
    const pugi::xml_parse_result result = doc.load_buffer(text.data(), text.size(), pugi::parse_default, pugi::encoding_utf8);
    if (!result)
      throw Error(name + ":" + std::to_string(lineNumberAt(text, size_t(std::max<ptrdiff_t>(result.offset, 0)))) +
                  ": XML syntax error: " + result.description());
    const pugi::xml_node root = doc.document_element();
    if (!root) {
      if (site) m_document.fail(*site, "the included file " + name + " holds no element");
      throw Error(name + ":1: the file holds no XML element (expected <scene version=\"...\">)");
    }
    const XmlNode described = rawNode(root, file);
    const std::string* version = described.attribute("version");
    if (!version) m_document.fail(described, "missing version attribute (Mitsuba's files carry version=\"3.0.0\" or similar)");
    int major = 0;
    if (!parseVersion(*version, major)) m_document.fail(described, "invalid version \"" + *version + "\" (expected e.g. \"3.0.0\")");
    if (major < 2 || major > 3)
      m_document.fail(described, "version " + *version +
                                     ": vktg reads Mitsuba 2 and 3 files (versions 2.x and 3.x); older files need Mitsuba's upgrade");
    return root;
  }

  static bool hasElementChild(const pugi::xml_node& element) {
    return bool(element.find_child([](const pugi::xml_node& n) { return n.type() == pugi::node_element; }));
  }

  // The element's tag, location and attributes as written.
  static XmlNode rawNode(const pugi::xml_node& element, uint32_t file) {
    XmlNode node;
    node.tag = element.name();
    node.file = file;
    node.offset = size_t(std::max<ptrdiff_t>(element.offset_debug(), 0));
    for (const pugi::xml_attribute& a : element.attributes()) node.attributes.emplace_back(a.name(), a.value());
    return node;
  }

  // The element with its attributes substituted (its children follow in convertChildren).
  XmlNode startNode(const pugi::xml_node& element, uint32_t file) {
    XmlNode node = rawNode(element, file);
    if (++m_elements > kMaxElements)
      m_document.fail(node, "more than " + std::to_string(kMaxElements) + " elements in the scene and its includes");
    for (auto& [key, value] : node.attributes) value = substitute(value, node);
    return node;
  }

  // Mitsuba's substitution: every $name a parameter defines, longest names first; "\$" stands for a
  // literal '$'; any other '$' left is an undefined parameter.
  std::string substitute(const std::string& text, const XmlNode& node) {
    if (text.find('$') == std::string::npos) return text;
    std::string out = text;
    for (Parameter& p : m_parameters) {
      const std::string key = "$" + p.name;
      for (size_t pos = out.find(key); pos != std::string::npos; pos = out.find(key, pos)) {
        if (pos > 0 && out[pos - 1] == '\\') {
          pos += key.size();
          continue;
        }
        out.replace(pos, key.size(), p.value);
        p.used = true;
        pos += p.value.size();
        if (out.size() > kMaxAttributeLength)
          m_document.fail(node, "an attribute grows past " + std::to_string(kMaxAttributeLength) + " bytes by $" + p.name);
      }
    }
    for (size_t pos = out.find('$'); pos != std::string::npos; pos = out.find('$', pos + 1)) {
      if (pos > 0 && out[pos - 1] == '\\') continue;
      size_t end = pos + 1;
      while (end < out.size() && (std::isalnum(static_cast<unsigned char>(out[end])) || out[end] == '_')) ++end;
      const std::string name = out.substr(pos + 1, end - pos - 1);
      m_document.fail(node, name.empty() ? "a '$' without a parameter name (write \\$ for a literal '$')"
                                          : "undefined parameter $" + name +
                                                " (give it a <default name=\"" + name + "\" value=\"...\"/> or -D " + name + "=VALUE)");
    }
    for (size_t pos = out.find("\\$"); pos != std::string::npos; pos = out.find("\\$", pos + 1)) out.erase(pos, 1);
    return out;
  }

  static void requireAttributes(const XmlDocument& document, const XmlNode& node, std::initializer_list<std::string_view> required,
                                std::initializer_list<std::string_view> optional) {
    for (const auto& [key, value] : node.attributes)
      if (std::find(required.begin(), required.end(), key) == required.end() &&
          std::find(optional.begin(), optional.end(), key) == optional.end())
        document.fail(node, "unexpected attribute \"" + key + "\"");
    for (std::string_view key : required)
      if (!node.attribute(key)) document.fail(node, "missing required attribute \"" + std::string(key) + "\"");
  }

  void convertChildren(const pugi::xml_node& element, uint32_t file, std::vector<XmlNode>& out, size_t depth) {
    for (const pugi::xml_node& child : element.children()) {
      if (child.type() != pugi::node_element) continue;
      XmlNode node = startNode(child, file);
      if (depth >= kMaxNesting) m_document.fail(node, "elements nested deeper than " + std::to_string(kMaxNesting));
      if (node.tag == "default") {
        requireAttributes(m_document, node, {"name", "value"}, {});
        const std::string& name = *node.attribute("name");
        if (!isValidDefineName(name)) m_document.fail(node, "a parameter name uses only letters, digits and '_'");
        if (hasElementChild(child)) m_document.fail(node, "a <default> holds no elements");
        // The first value wins: a -D define, or an earlier <default> of the same name.
        if (std::none_of(m_parameters.begin(), m_parameters.end(), [&](const Parameter& p) { return p.name == name; })) {
          m_parameters.push_back({name, *node.attribute("value"), false, true});
          sortParameters();
        }
        continue;
      }
      if (node.tag == "include") {
        include(node, child, file, out, depth);
        continue;
      }
      convertChildren(child, file, node.children, depth + 1);
      out.push_back(std::move(node));
    }
  }

  // <include filename="..."/>: a file relative to the including file's folder. A <scene> root
  // contributes its children where the include stands; any other root element stands there itself
  // (named by the include's name attribute, if it has one).
  void include(const XmlNode& site, const pugi::xml_node& element, uint32_t file, std::vector<XmlNode>& out, size_t depth) {
    requireAttributes(m_document, site, {"filename"}, {"name"});
    if (hasElementChild(element)) m_document.fail(site, "an <include> holds no elements");
    const fs::path named = *site.attribute("filename");
    const fs::path path = named.is_absolute() ? named : m_document.m_files[file].path.parent_path() / named;
    const fs::path key = canonical(path);
    if (std::find(m_includeStack.begin(), m_includeStack.end(), key) != m_includeStack.end()) {
      std::string chain;
      for (const fs::path& p : m_includeStack) chain += p.string() + " -> ";
      m_document.fail(site, "include cycle: " + chain + key.string());
    }
    if (m_includeStack.size() > kMaxIncludeDepth)
      m_document.fail(site, "includes nested deeper than " + std::to_string(kMaxIncludeDepth));
    const uint32_t included = readFile(path, &site);
    pugi::xml_document doc;
    const pugi::xml_node root = parse(included, doc, &site);
    m_includeStack.push_back(key);
    if (std::string_view(root.name()) == "scene") {
      XmlNode scene = startNode(root, included);
      for (const auto& [name, value] : scene.attributes)
        if (name != "version" && name != "id" && name != "name")
          m_document.fail(scene, "unexpected attribute \"" + name + "\" (a <scene> takes version, id and name)");
      convertChildren(root, included, out, depth);
    } else {
      XmlNode node = startNode(root, included);
      std::erase_if(node.attributes, [](const auto& a) { return a.first == "version"; });
      if (const std::string* name = site.attribute("name")) {
        std::erase_if(node.attributes, [](const auto& a) { return a.first == "name"; });
        node.attributes.emplace_back("name", *name);
      }
      convertChildren(root, included, node.children, depth + 1);
      out.push_back(std::move(node));
    }
    m_includeStack.pop_back();
  }

  void indexIds(const XmlNode& node) {
    if (node.tag != "ref")
      if (const std::string* id = node.attribute("id")) {
        if (id->empty()) m_document.fail(node, "an empty id");
        const auto [it, inserted] = m_document.m_ids.emplace(*id, &node);
        if (!inserted)
          m_document.fail(node, "duplicate id \"" + *id + "\" (first at " + m_document.location(*it->second) + ")");
      }
    for (const XmlNode& child : node.children) indexIds(child);
  }

  XmlDocument& m_document;
  std::vector<Parameter> m_parameters;
  std::vector<fs::path> m_includeStack;
  size_t m_elements = 0;
};

XmlDocument::XmlDocument(const fs::path& path, const SceneDefines& defines) { XmlExpander(*this, defines).run(path); }

}  // namespace vktg
