// The one error type for bad input: names the file, the place in it and the reason.
#pragma once
#include <stdexcept>
#include <string>

namespace purl {

class InputError : public std::runtime_error {
public:
    InputError(std::string file, std::string place, std::string reason)
        : std::runtime_error(compose(file, place, reason)),
          file_(std::move(file)), place_(std::move(place)), reason_(std::move(reason)) {}
    const std::string& file() const { return file_; }
    const std::string& place() const { return place_; }
    const std::string& reason() const { return reason_; }

private:
    static std::string compose(const std::string& f, const std::string& p, const std::string& r) {
        std::string m = f.empty() ? std::string("<input>") : f;
        if (!p.empty()) m += ": " + p;
        return m + ": " + r;
    }
    std::string file_, place_, reason_;
};

}  // namespace purl
