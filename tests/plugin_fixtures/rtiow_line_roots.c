/* The "Ray Tracing in One Weekend" sphere (v4.0, sphere::hit: half-b, the
 * nearest root in (t_min, t_max)) pasted into examples/plugin_rtg/rtg_sphere.c,
 * whose description still declares RAYVERIFY_LINE_ROOTS: the mistake a new user
 * makes, which the audit's contract hint must name. The body is the
 * nearest-in-interval template's own; only the description is the line-roots
 * template's. */
#define rayverify_plugin_describe nearest_in_interval_describe
#include "nearest_in_interval.c"
#undef rayverify_plugin_describe

RAYVERIFY_PLUGIN_EXPORT const rayverify_plugin_info* rayverify_plugin_describe(void) {
    static const rayverify_plugin_info info = {
        RAYVERIFY_PLUGIN_ABI_VERSION, "rtiow_pasted", "Ray Tracing in One Weekend v4.0, sphere::hit", NULL,
        RAYVERIFY_LINE_ROOTS,         0,              1,                                              0,
        "disc == 0"};
    return &info;
}
