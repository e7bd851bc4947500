// Blender's perspective camera: sensor fit, lens, shift and clipping computed the way
// Blender computes its view plane, plus one-pixel ray differentials on every ray.
#pragma once
#include "math/ray.h"
#include "scene/scene.h"

namespace purl {

class Camera {
public:
    Camera(const CameraDesc& desc, const FilmDesc& film);

    // Ray through film position (x, y) in pixels, x to the right, y down from the top-left
    // corner (pixel (i, j) covers [i, i+1] x [j, j+1]).
    Ray generate_ray(float x, float y) const;
    // Film position of a world point; false when it is behind the camera.
    bool project(Vec3 world_point, float& x, float& y) const;
    // Distance along the camera's viewing axis (Blender's Depth pass).
    float view_depth(Vec3 world_point) const;
    Vec3 position() const { return origin_; }
    // A world direction in Blender's camera space (x right, y up, z toward the viewer).
    Vec3 to_camera(Vec3 world_direction) const {
        return {dot(world_direction, right_), dot(world_direction, up_), dot(world_direction, back_)};
    }

private:
    Vec3 camera_direction(float x, float y) const;  // unnormalised, camera space, z = -1

    Vec3 origin_, right_, up_, back_;  // orthonormal camera axes in world space
    float plane_left_ = 0, plane_top_ = 0;   // view-plane coordinates (at z = -1) of the film corner
    float plane_dx_ = 0, plane_dy_ = 0;      // view-plane step per pixel in x and y
    float clip_start_ = 0, clip_end_ = 0;
};

}  // namespace purl
