#include "reference/explicit_models.h"

#include "scene/input_error.h"

namespace purl {

SceneDesc make_explicit_scene(const SceneDesc& scene, YarnModel model) {
    if (model == YarnModel::Bysdf) return scene;
    throw InputError(scene.source, "render.model", "the explicit reference models are being built (issue 5)");
}

}  // namespace purl
