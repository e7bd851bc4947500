// A fitting target: a scene (camera, lights, yarn geometry, starting material) and the
// image it should reproduce, optionally with a mask weighting the pixels that count.
#pragma once
#include <string>
#include <vector>

#include "scene/scene.h"

namespace purl {

struct FitTarget {
    std::string name;            // for messages and the preset's provenance
    SceneDesc scene;
    int width = 0, height = 0;
    std::vector<float> rgb;      // linear RGB, rows top to bottom
    std::vector<float> weight;   // per pixel in [0, 1]; empty = every pixel counts
};

// Reads a target image: EXR (a multilayer file's Combined pass, or plain R, G, B) or any image
// OpenImageIO reads. Throws InputError naming the file, and the pixel (x, y) for a NaN or
// infinite value.
void read_target_image(const std::string& path, int& width, int& height, std::vector<float>& rgb);

// Loads the scene and the image (and the mask: first channel, 0 = ignore, 1 = count) and
// checks that the image has the size the scene renders at.
FitTarget load_fit_target(const std::string& scene_path, const std::string& image_path,
                          const std::string& mask_path = "");

// The same check for a target built in memory (the Python module). Throws InputError.
void check_fit_target(const FitTarget& target);

}  // namespace purl
