#pragma once
/// The catalogue of a type library, made by sscs itself: docs/library.md and its thumbnails.
#include <string>
#include <vector>

#include "pipeline/type_listing.h"

namespace sscs {

/// `sscs types --format md --out FILE.md`: the catalogue of the loaded library: per type its
/// description, the notes and sources its file's header comments give, attributes (unit,
/// default, limits), rules, frames with their positions, a device's parts, joints and reach, and
/// a thumbnail rendered by sscs (img/library/TYPE.png beside FILE). Everything it writes is a
/// function of the library alone (no dates, no absolute paths), so a fresh one can be compared
/// with a committed one. Returns "" or why it could not write (render unavailable: throws
/// gl::RenderUnavailable).
std::string write_type_catalogue(const std::string& md_path, std::vector<ObjectType> types, const CompileOptions& instance_options,
                                 Sources& sources, Diagnostics& problems);

}  // namespace sscs
