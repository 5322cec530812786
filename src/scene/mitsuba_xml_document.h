// A Mitsuba 3 XML scene as a tree of elements, before any plugin is read (docs/scene-format.md,
// "Mitsuba 3 XML"): every <include> replaced by what it includes, every <default> taken into the
// parameter table (a command-line `-D name=value` wins over it), every $name in an attribute
// replaced, and every element's id indexed. Each element remembers its file and byte offset, so that
// every error reads "FILE:LINE: <element ...>: problem".
#pragma once
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "vktg/scene.h"

namespace vktg {

struct XmlNode {
  std::string tag;
  std::vector<std::pair<std::string, std::string>> attributes;  // $name replaced, in document order
  std::vector<XmlNode> children;                                 // child elements (comments and text dropped)
  uint32_t file = 0;   // which of the document's files holds the element
  size_t offset = 0;   // byte offset of the element in that file

  const std::string* attribute(std::string_view name) const;  // nullptr when absent
};

class XmlDocument {
 public:
  // Reads `path` (its root must be <scene version="2.x" or "3.x">) and every file it includes.
  // Fails naming file, line and element on a syntax error, an unreadable or cyclic include, an
  // undefined $name, a duplicate id, and a define that no $name uses (a typo must not pass).
  XmlDocument(const std::filesystem::path& path, const SceneDefines& defines);
  XmlDocument(const XmlDocument&) = delete;
  XmlDocument& operator=(const XmlDocument&) = delete;
  XmlDocument(XmlDocument&&) = default;

  const XmlNode& root() const { return *m_root; }
  // The element whose id attribute is `id` (refs excluded), or nullptr.
  const XmlNode* findId(std::string_view id) const;
  // Every id the document defines.
  std::vector<std::string> ids() const;
  // The scene file as named by the caller; relative file names of plugins resolve against its folder.
  const std::filesystem::path& mainFile() const { return m_files.front().path; }

  // "FILE:LINE" of the element.
  std::string location(const XmlNode& node) const;
  // The element as it starts in the file, with the attributes that identify it: <shape type="obj" id="wall">.
  static std::string describe(const XmlNode& node);
  // Throws vktg::Error "FILE:LINE: <element ...>: problem".
  [[noreturn]] void fail(const XmlNode& node, const std::string& problem) const;

 private:
  struct File {
    std::filesystem::path path;
    std::string text;
  };
  friend class XmlExpander;
  std::vector<File> m_files;
  std::unique_ptr<XmlNode> m_root;
  std::map<std::string, const XmlNode*, std::less<>> m_ids;
};

// Whether `name` can follow a '$' in an attribute: letters, digits and '_', at least one.
bool isValidDefineName(std::string_view name);

}  // namespace vktg
