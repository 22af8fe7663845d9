// Every integrator type a scene file can name, in the order error messages
// list them. Adding a type: its file in this folder, and one line here.
#include "renderer/integrator.h"

namespace isotrace {

std::unique_ptr<Integrator> readPathIntegrator(geometry::JsonObjectReader& r);
std::unique_ptr<Integrator> readWhittedIntegrator(geometry::JsonObjectReader& r);
std::unique_ptr<Integrator> makePathIntegrator(int maxDepth, int russianRouletteDepth, LightSampling lightSampling);

const Registry<IntegratorFactory>& integratorRegistry() {
    static const Registry<IntegratorFactory> registry({
        {"path", readPathIntegrator},
        {"whitted", readWhittedIntegrator},
    });
    return registry;
}

std::unique_ptr<Integrator> makeDefaultIntegrator() { return makePathIntegrator(8, 3, LightSampling::Tree); }

}  // namespace isotrace
