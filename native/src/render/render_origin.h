// Renders happen in a frame centred on the cloth. A scene far from the world origin (a garment
// at (1e4, 1e4, 0) in a Blender file) then keeps, in every computation after loading, the
// precision of one at the origin: ray origins, tube exits, the ply search, light samples. Only
// the rounding of its input to floats remains. Nothing in the image depends on where the scene
// is (depth, normals, ids and ply coordinates are all relative), and subtracting a nearby float
// is exact (Sterbenz's lemma), so the move adds no error near the origin chosen.
#pragma once
#include "scene/scene.h"

namespace purl {

// The centre of the yarns' bounding box; without yarns the meshes', without either the camera.
Vec3 render_origin(const SceneDesc& scene);
// Moves every position in the scene by -origin (camera, lights, curves, ply origins, meshes)
// and adds it to SceneDesc::origin, which keeps the world position of the scene's zero.
void move_to_render_origin(SceneDesc& scene, Vec3 origin);

}  // namespace purl
