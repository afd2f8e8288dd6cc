// The catalog item as the shop exports see it (export_items.h).
#include "garmcap/daemon/export_items.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace garmcap::daemon {
namespace {

// A back shot (issue 17) gives the shop its ghost-mannequin front first and the back second;
// without one the plain front goes alone. Cut-outs, crops, WebP copies and stills never go.
TEST(ShopImages, TheGhostFrontThenTheBackWhenABackShotWasTaken) {
  Item it;
  it.id = 7;
  it.sku = "SK-7";
  auto image = [](const std::string& kind, const std::string& type) {
    return ImageRef{kind, "sha-" + kind, type, 1};
  };
  it.images = {image("dressed", "image/png"),       image("cutout", "image/png"),
               image("product", "image/jpeg"),      image("product_webp", "image/webp"),
               image("product_4x5", "image/jpeg"),  image("back", "image/png"),
               image("cutout_back", "image/png"),   image("product_back", "image/jpeg"),
               image("product_ghost", "image/jpeg")};
  auto shopPaths = [&it] {
    std::vector<std::string> paths;
    for (const auto& im : toExportItem(it, std::nullopt).images)
      paths.push_back(im.path);
    return paths;
  };
  EXPECT_EQ(shopPaths(),
            (std::vector<std::string>{"images/7-product_ghost.jpg", "images/7-product_back.jpg"}));

  it.images = {image("cutout", "image/png"), image("product", "image/jpeg"),
               image("product_4x5", "image/jpeg")};
  EXPECT_EQ(shopPaths(), (std::vector<std::string>{"images/7-product.jpg"}));

  // A back shot whose ghost could not be made (no neck opening): the plain front, then the back.
  it.images.push_back(image("product_back", "image/jpeg"));
  EXPECT_EQ(shopPaths(),
            (std::vector<std::string>{"images/7-product.jpg", "images/7-product_back.jpg"}));
}

}  // namespace
}  // namespace garmcap::daemon
