// findContacts (src/scene/contacts.cpp): the edges of one shape that rest on another, the vertices
// that touch one, and the edges that pass through one, between shapes of which one moves.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "scene/contacts.h"
#include "vktg/prepared_scene.h"
#include "vktg/scene.h"

namespace vktg {
namespace {

constexpr float kTolerance = 1e-4f;

// A 4 m floor (shape 0) and `second` (shape 1).
Scene floorAnd(const std::string& second) {
  return parseSceneJson(R"({"version": 1,
    "camera": {"type": "perspective", "position": [0, 1, 3], "look_at": [0, 0, 0]},
    "materials": {"m": {"type": "diffuse", "albedo": 0.5}},
    "shapes": [
      {"name": "floor", "type": "rectangle", "material": "m", "transform": {"rotate": [-90, 0, 0], "scale": 2}},
      )" + second + R"(,
      {"name": "lamp", "type": "rectangle", "material": "m", "emission": 1,
       "transform": {"translate": [0, 3, 0], "rotate": [90, 0, 0], "scale": 0.1}}]})",
                        "contacts.json", ".");
}

std::string boxAt(double y) {
  return R"({"name": "box", "type": "cube", "material": "m", "transform": {"translate": [0.3, )" + std::to_string(y) +
         R"(, 0], "scale": 0.25}})";
}

std::vector<ShapeContact> contactsOf(const Scene& scene, std::vector<bool> moving) {
  return findContacts(prepareScene(scene), moving, kTolerance);
}

TEST(Contacts, ABoxRestingOnAFloorHasItsBottomEdgesOnIt) {
  const Scene scene = floorAnd(boxAt(0.25));
  const std::vector<ShapeContact> contacts = contactsOf(scene, {false, true, false});
  ASSERT_EQ(contacts.size(), 1u);
  EXPECT_EQ(contacts[0].shape, 1u);
  EXPECT_EQ(contacts[0].other, 0u);
  EXPECT_EQ(contacts[0].restingEdges, 5u) << "four bottom edges and the bottom face's diagonal";
  EXPECT_EQ(contacts[0].crossingEdges, 0u);
  EXPECT_EQ(contacts[0].touchingVertices, 4u);
  const std::vector<std::string> lines = describeContacts(scene, contacts);
  ASSERT_EQ(lines.size(), 1u);
  EXPECT_NE(lines[0].find("5 edges of 'box' lie on 'floor'"), std::string::npos) << lines[0];
}

TEST(Contacts, NothingWhereShapesAreApartOrNeitherMoves) {
  EXPECT_TRUE(contactsOf(floorAnd(boxAt(0.3)), {false, true, false}).empty()) << "5 cm above the floor";
  EXPECT_TRUE(contactsOf(floorAnd(boxAt(0.25)), {false, false, false}).empty()) << "nothing moves";
  // The floor moving under a static box is a contact too (the box rests on it).
  EXPECT_EQ(contactsOf(floorAnd(boxAt(0.25)), {true, false, false}).size(), 1u);
}

TEST(Contacts, ABoxSunkIntoTheFloorInterpenetrates) {
  const Scene scene = floorAnd(boxAt(0.15));
  const std::vector<ShapeContact> contacts = contactsOf(scene, {false, true, false});
  ASSERT_EQ(contacts.size(), 1u);
  // The box's four vertical edges and a diagonal of each side face, and the floor's diagonal, which
  // passes through the box.
  EXPECT_EQ(contacts[0].crossingEdges, 9u);
  const std::vector<std::string> lines = describeContacts(scene, contacts);
  EXPECT_NE(lines.at(0).find("warning: 'floor' and 'box' interpenetrate"), std::string::npos) << lines[0];
}

TEST(Contacts, ASphereOnAPlaneTouchesItAtItsLowestVertex) {
  Scene scene = floorAnd(R"({"name": "ball", "type": "sphere", "subdivisions": 2, "material": "m",
                             "transform": {"translate": [0, 1, 0], "scale": 0.5}})");
  float lowest = 1e9f;
  for (const glm::vec3& p : scene.shapes[1].positions) lowest = std::min(lowest, p.y);
  for (glm::vec3& p : scene.shapes[0].positions) p.y = lowest;
  const std::vector<ShapeContact> contacts = contactsOf(scene, {false, true, false});
  ASSERT_EQ(contacts.size(), 1u);
  EXPECT_EQ(contacts[0].restingEdges, 0u);
  EXPECT_GE(contacts[0].touchingVertices, 1u);
  EXPECT_NE(describeContacts(scene, contacts).at(0).find("vertices of 'ball' touch 'floor'"), std::string::npos);
}

TEST(Contacts, AWallEndingOnTheNextWallRestsOnItWithoutCrossing) {
  // A T-junction: the wall across ends on the long wall, whose diagonal meets it exactly at its edge.
  const Scene scene = floorAnd(R"({"name": "across", "type": "rectangle", "material": "m",
                                   "transform": {"translate": [0, 0.5, -1], "scale": [2, 0.5, 1]}})");
  const std::vector<ShapeContact> contacts = contactsOf(scene, {false, true, false});
  ASSERT_EQ(contacts.size(), 1u);
  EXPECT_EQ(contacts[0].shape, 1u);
  EXPECT_EQ(contacts[0].restingEdges, 1u);
  EXPECT_EQ(contacts[0].crossingEdges, 0u);
}

}  // namespace
}  // namespace vktg
