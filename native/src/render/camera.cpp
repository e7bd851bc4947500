#include "render/camera.h"

#include <cmath>

namespace purl {

Camera::Camera(const CameraDesc& desc, const FilmDesc& film) {
    origin_ = desc.to_world.translation();
    // Blender ignores camera scale: use the normalised axes.
    right_ = normalize(desc.to_world.column(0));
    up_ = normalize(desc.to_world.column(1));
    back_ = normalize(desc.to_world.column(2));
    clip_start_ = desc.clip_start;
    clip_end_ = desc.clip_end;

    // Blender's view plane (BKE_camera_params_compute_viewplane), in pixel units first.
    const float width = static_cast<float>(film.width), height = static_cast<float>(film.height);
    const float aspect_x = film.pixel_aspect_x, aspect_y = film.pixel_aspect_y;
    const float y_correction = aspect_y / aspect_x;
    SensorFit fit = desc.sensor_fit;
    const float sensor = fit == SensorFit::Vertical ? desc.sensor_height_mm : desc.sensor_width_mm;
    if (fit == SensorFit::Auto)
        fit = aspect_x * width >= aspect_y * height ? SensorFit::Horizontal : SensorFit::Vertical;
    const float view_factor = fit == SensorFit::Horizontal ? width : y_correction * height;
    const float pixel_size = sensor / desc.lens_mm / view_factor;  // view-plane units per pixel at z = -1

    const float dx = desc.shift_x * view_factor, dy = desc.shift_y * view_factor;
    plane_left_ = (-0.5f * width + dx) * pixel_size;
    plane_top_ = (0.5f * y_correction * height + dy) * pixel_size;
    plane_dx_ = pixel_size;
    plane_dy_ = -y_correction * pixel_size;
}

Vec3 Camera::camera_direction(float x, float y) const {
    return {plane_left_ + x * plane_dx_, plane_top_ + y * plane_dy_, -1.0f};
}

Ray Camera::generate_ray(float x, float y) const {
    auto to_world = [&](Vec3 d) { return right_ * d.x + up_ * d.y + back_ * d.z; };
    const Vec3 d = camera_direction(x, y);
    Ray ray;
    ray.direction = normalize(to_world(d));
    // Clipping is along the view axis, so the ray parameter scales with the direction's length.
    const float axis_to_ray = length(d);
    ray.origin = origin_;
    ray.tmin = clip_start_ * axis_to_ray;
    ray.tmax = clip_end_ * axis_to_ray;
    ray.has_differentials = true;
    ray.rx_origin = origin_;
    ray.ry_origin = origin_;
    ray.rx_direction = normalize(to_world(camera_direction(x + 1.0f, y)));
    ray.ry_direction = normalize(to_world(camera_direction(x, y + 1.0f)));
    return ray;
}

bool Camera::project(Vec3 world_point, float& x, float& y) const {
    const Vec3 v = world_point - origin_;
    const float depth = -dot(v, back_);
    if (!(depth > 0.0f)) return false;
    const float px = dot(v, right_) / depth, py = dot(v, up_) / depth;
    x = (px - plane_left_) / plane_dx_;
    y = (py - plane_top_) / plane_dy_;
    return true;
}

float Camera::view_depth(Vec3 world_point) const { return -dot(world_point - origin_, back_); }

}  // namespace purl
