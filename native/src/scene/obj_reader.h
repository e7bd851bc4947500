// Minimal Wavefront OBJ reading: vertices and polygon faces (fanned into triangles).
#pragma once
#include <string>

#include "scene/scene.h"

namespace purl {

// Fills vertices and indices of `mesh`; throws InputError naming the line on bad input.
void read_obj(const std::string& path, MeshDesc& mesh);

}  // namespace purl
