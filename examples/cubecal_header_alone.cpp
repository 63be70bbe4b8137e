// The umbrella header alone in a translation unit: it must compile as a
// downstream project sees it (installed, with nothing but cubecal::core),
// so every public header of the core it includes stands on its own.
#include <cubecal/cubecal.hpp>
