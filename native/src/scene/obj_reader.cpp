#include "scene/obj_reader.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#include "base/input_error.h"

namespace purl {

namespace {

// Longer lines are not OBJ a person or exporter writes; without a cap, one line of a
// several-GB file (or a device) would be read into memory whole.
constexpr size_t kMaxLineBytes = size_t(1) << 20;
// Triangle indices are uint32.
constexpr size_t kMaxVertices = size_t(1) << 31;

// Reads one line of at most kMaxLineBytes into `line`; false at the end of the file.
bool read_line(std::istream& in, std::vector<char>& buffer, std::string& line, const std::string& path,
               size_t line_number) {
    buffer.resize(kMaxLineBytes + 2);
    in.getline(buffer.data(), static_cast<std::streamsize>(buffer.size()));
    if (in.bad()) throw InputError(path, "line " + std::to_string(line_number), "read error");
    if (in.gcount() == 0 && in.eof()) return false;
    if (in.fail() && !in.eof())  // the buffer filled before a line end
        throw InputError(path, "line " + std::to_string(line_number),
                         "line longer than " + std::to_string(kMaxLineBytes) + " bytes");
    line.assign(buffer.data());
    return true;
}

}  // namespace

void read_obj(const std::string& path, MeshDesc& mesh) {
    // A FIFO would block: only regular files.
    std::error_code ec;
    const std::filesystem::file_status status = std::filesystem::status(path, ec);
    if (ec || !std::filesystem::exists(status)) throw InputError(path, "", "cannot open file");
    if (!std::filesystem::is_regular_file(status)) throw InputError(path, "", "not a regular file");
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(path, "", "cannot open file");
    std::string line;
    std::vector<char> buffer;
    size_t line_number = 0;
    const size_t first_vertex = mesh.vertices.size();
    while (read_line(in, buffer, line, path, line_number + 1)) {
        ++line_number;
        if (!line.empty() && line.back() == '\r') line.pop_back();  // Windows line ends
        std::istringstream ls(line);
        std::string tag;
        ls >> tag;
        const std::string place = "line " + std::to_string(line_number);
        if (tag == "v") {
            Vec3 v;
            if (!(ls >> v.x >> v.y >> v.z)) throw InputError(path, place, "vertex needs three numbers");
            if (!is_finite(v)) throw InputError(path, place, "vertex is not finite");
            if (mesh.vertices.size() >= kMaxVertices)
                throw InputError(path, place, "more than " + std::to_string(kMaxVertices) + " vertices");
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
