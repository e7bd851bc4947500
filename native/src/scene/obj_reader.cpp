#include "scene/obj_reader.h"

#include <cmath>
#include <fstream>
#include <sstream>

#include "scene/input_error.h"

namespace purl {

void read_obj(const std::string& path, MeshDesc& mesh) {
    std::ifstream in(path);
    if (!in) throw InputError(path, "", "cannot open file");
    std::string line;
    size_t line_number = 0;
    const size_t first_vertex = mesh.vertices.size();
    while (std::getline(in, line)) {
        ++line_number;
        std::istringstream ls(line);
        std::string tag;
        ls >> tag;
        const std::string place = "line " + std::to_string(line_number);
        if (tag == "v") {
            Vec3 v;
            if (!(ls >> v.x >> v.y >> v.z)) throw InputError(path, place, "vertex needs three numbers");
            if (!is_finite(v)) throw InputError(path, place, "vertex is not finite");
            mesh.vertices.push_back(v);
        } else if (tag == "f") {
            std::vector<uint32_t> face;
            std::string corner;
            while (ls >> corner) {
                // "7", "7/1" or "7/1/3": only the position index matters here.
                long index = 0;
                try {
                    index = std::stol(corner.substr(0, corner.find('/')));
                } catch (...) {
                    throw InputError(path, place, "bad face index \"" + corner + "\"");
                }
                const long count = static_cast<long>(mesh.vertices.size() - first_vertex);
                if (index < 0) index = count + index + 1;  // negative indices count back
                if (index < 1 || index > count)
                    throw InputError(path, place, "face index " + corner + " out of range");
                face.push_back(static_cast<uint32_t>(first_vertex + index - 1));
            }
            if (face.size() < 3) throw InputError(path, place, "face needs at least 3 vertices");
            for (size_t i = 1; i + 1 < face.size(); ++i)
                mesh.indices.insert(mesh.indices.end(), {face[0], face[i], face[i + 1]});
        }
    }
    if (mesh.indices.empty()) throw InputError(path, "", "no faces");
}

}  // namespace purl
