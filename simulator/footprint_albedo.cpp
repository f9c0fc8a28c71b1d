#include "simulator/footprint_albedo.hpp"

#include "simulator/texture.hpp"

namespace tlsmon::sim {

double footprint_albedo(const Hit& h, const Texture& texture, double blur) {
    if (h.surface == Surface::pier || h.surface == Surface::deck) {
        return concrete_albedo(texture, h.face, h.uv.x(), h.uv.y(), blur);
    }
    if (h.surface == Surface::checkerboard) return checkerboard_albedo(h.uv.x(), h.uv.y(), blur);
    return h.albedo;
}

}  // namespace tlsmon::sim
