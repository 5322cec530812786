// Command-buffer labels are left out under validation layers whose label tracking races with
// their own queue thread (host/vk_context.h, labelsAreSafe).
#include <gtest/gtest.h>

#include "vk/vk_context.h"

namespace vktg {
namespace {

TEST(ValidationLabels, LeftOutUnderLayersThatEraseThemWithoutALock) {
  EXPECT_TRUE(labelsAreSafe(0)) << "no validation layer";
  EXPECT_FALSE(labelsAreSafe(VK_MAKE_API_VERSION(0, 1, 3, 239))) << "Debian 12's layer";
  EXPECT_FALSE(labelsAreSafe(VK_MAKE_API_VERSION(0, 1, 3, 242)));
  EXPECT_TRUE(labelsAreSafe(VK_MAKE_API_VERSION(0, 1, 3, 243)));
  EXPECT_TRUE(labelsAreSafe(VK_MAKE_API_VERSION(0, 1, 4, 0)));
}

}  // namespace
}  // namespace vktg
