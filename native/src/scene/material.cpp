#include "scene/scene.h"

namespace purl {

MaterialDesc::MaterialDesc() : bysdf(default_bysdf_params()), yarn(default_yarn_description()) {
    apply_defaults(placeholder, placeholder_param_table());
}

}  // namespace purl
