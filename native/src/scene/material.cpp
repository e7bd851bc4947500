#include "scene/scene.h"

namespace purl {

MaterialDesc::MaterialDesc() : bysdf(default_bysdf_params()), yarn(default_yarn_description()) {
    apply_defaults(placeholder, placeholder_param_table());
}

const char* material_model_name(MaterialModel model) {
    switch (model) {
        case MaterialModel::Placeholder: return "placeholder";
        case MaterialModel::Fiber: return "fiber";
        case MaterialModel::Ply: return "ply";
        case MaterialModel::Bysdf: break;
    }
    return "bysdf";
}

}  // namespace purl
