#include "core/ray_sphere_case.h"

namespace rayverify {

const char* invalid_reason_name(invalid_reason r) {
    switch (r) {
        case invalid_reason::none: return "valid";
        case invalid_reason::non_finite_input: return "non_finite_input";
        case invalid_reason::zero_direction: return "zero_direction";
        case invalid_reason::negative_radius: return "negative_radius";
        case invalid_reason::not_representable: return "not_representable_in_precision";
        case invalid_reason::bad_interval: return "bad_interval";
    }
    return "?";
}

}  // namespace rayverify
