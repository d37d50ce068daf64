#pragma once
/// A contact sheet: thumbnails in a grid, each labelled, for a run's step ends.
#include <string>
#include <vector>

#include "render/image.h"
#include "render/text.h"

namespace sscs {

struct Thumbnail {
  Image image;
  std::string label;
};

/// `image` scaled to `width` (height keeping the aspect) by averaging the pixels each covers.
Image downscale(const Image& image, int width);

/// Thumbnails in rows of `columns`, each with its label under it, on a light background.
Image contact_sheet(const std::vector<Thumbnail>& thumbs, const Font& font, int columns = 4);

}  // namespace sscs
