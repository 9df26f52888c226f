/* wrsim_osdi.h: the binary interface of an OSDI 0.3 device library, as ngspice 46 loads it (`pre_osdi`).
 *
 * Written for wrsim's generated device code (wrsim.backend.ngspice.osdi) from the interface's public
 * description and from ngspice's loader (src/osdi/osdiregistry.c, osdisetup.c, osdiload.c): the field order and
 * types below are what that loader reads; the names are wrsim's. A library exports OSDI_VERSION_MAJOR = 0,
 * OSDI_VERSION_MINOR = 3, OSDI_NUM_DESCRIPTORS and the array OSDI_DESCRIPTORS; without OSDI_DESCRIPTOR_SIZE
 * ngspice 46 steps through the array with the size of the 0.3 descriptor declared here.
 *
 * What ngspice does with a device (the facts the generator relies on):
 * - every offset below is from the start of the device's own instance data; UINT32_MAX means "none";
 * - node_mapping (uint32 per node) receives the simulator's equation numbers (0: ground), jacobian_ptr_resist
 *   (a double * per Jacobian entry) the matrix element of (equation, unknown), react_ptr_off of an entry (when
 *   not UINT32_MAX) the slot for its imaginary part (AC);
 * - a node whose react_residual_off is not UINT32_MAX gets two states: ngspice integrates the charge read there
 *   and subtracts its time derivative from the right-hand side; the device loads alpha * dQ/dx (alpha = ag[0]);
 * - ngspice always offers the instance parameters `dt` and `temp` and, unless the device declares `$mfactor`,
 *   an `m` it leaves undescribed: a device declares `$mfactor`;
 * - eval may run for several instances at once (OpenMP): it writes only its own instance. */
#ifndef WRSIM_OSDI_H
#define WRSIM_OSDI_H

#include <stdbool.h>
#include <stdint.h>

#define WRSIM_OSDI_NONE UINT32_MAX

/* parameter flags */
#define WRSIM_PARA_REAL 0u
#define WRSIM_PARA_INST (1u << 30)

/* access() flags */
#define WRSIM_ACCESS_SET 1u
#define WRSIM_ACCESS_INSTANCE 4u

/* sim_info flags */
#define WRSIM_ANALYSIS_AC 4096u /* a small-signal analysis: the evaluation at the operating point it linearises */

/* Jacobian entry flags */
#define WRSIM_JAC_RESIST 4u
#define WRSIM_JAC_REACT 8u

typedef struct {
    char **names;
    double *vals;
    char **names_str;
    char **vals_str;
} wrsim_osdi_sim_paras;

typedef struct {
    wrsim_osdi_sim_paras paras;
    double abstime; /* 0 outside a transient */
    double *prev_solve; /* the solution of the last Newton iteration, by equation number */
    double *prev_state;
    double *next_state;
    uint32_t flags;
} wrsim_osdi_sim_info;

typedef struct {
    uint32_t code;
    uint32_t parameter_id;
} wrsim_osdi_init_error;

typedef struct {
    uint32_t flags;
    uint32_t num_errors;
    wrsim_osdi_init_error *errors;
} wrsim_osdi_init_info;

typedef struct {
    uint32_t node_1; /* a Jacobian entry: the equation (row) */
    uint32_t node_2; /* and the unknown (column) */
} wrsim_osdi_node_pair;

typedef struct {
    wrsim_osdi_node_pair nodes;
    uint32_t react_ptr_off;
    uint32_t flags;
} wrsim_osdi_jacobian_entry;

typedef struct {
    char *name;
    char *units;
    char *residual_units;
    uint32_t resist_residual_off;
    uint32_t react_residual_off;
    uint32_t resist_limit_rhs_off;
    uint32_t react_limit_rhs_off;
    bool is_flow;
} wrsim_osdi_node;

typedef struct {
    char **name; /* the name, then its aliases */
    uint32_t num_alias;
    char *description;
    char *units;
    uint32_t flags;
    uint32_t len; /* 0: a scalar */
} wrsim_osdi_param;

typedef struct {
    char *name;
    wrsim_osdi_node_pair nodes;
} wrsim_osdi_noise_source;

typedef struct {
    char *name;
    uint32_t num_nodes;
    uint32_t num_terminals;
    wrsim_osdi_node *nodes;
    uint32_t num_jacobian_entries;
    wrsim_osdi_jacobian_entry *jacobian_entries;
    uint32_t num_collapsible;
    wrsim_osdi_node_pair *collapsible;
    uint32_t collapsed_offset;
    wrsim_osdi_noise_source *noise_sources;
    uint32_t num_noise_src;
    uint32_t num_params;
    uint32_t num_instance_params;
    uint32_t num_opvars;
    wrsim_osdi_param *param_opvar;
    uint32_t node_mapping_offset;
    uint32_t jacobian_ptr_resist_offset;
    uint32_t num_states;
    uint32_t state_idx_off;
    uint32_t bound_step_offset;
    uint32_t instance_size;
    uint32_t model_size;
    void *(*access)(void *inst, void *model, uint32_t id, uint32_t flags);
    void (*setup_model)(void *handle, void *model, wrsim_osdi_sim_paras *sim_params, wrsim_osdi_init_info *res);
    void (*setup_instance)(void *handle, void *inst, void *model, double temperature, uint32_t num_terminals,
                           wrsim_osdi_sim_paras *sim_params, wrsim_osdi_init_info *res);
    uint32_t (*eval)(void *handle, void *inst, const void *model, const wrsim_osdi_sim_info *info);
    void (*load_noise)(void *inst, void *model, double freq, double *noise_dens);
    void (*load_residual_resist)(void *inst, void *model, double *dst);
    void (*load_residual_react)(void *inst, void *model, double *dst);
    void (*load_limit_rhs_resist)(void *inst, void *model, double *dst);
    void (*load_limit_rhs_react)(void *inst, void *model, double *dst);
    void (*load_spice_rhs_dc)(void *inst, void *model, double *dst, double *prev_solve);
    void (*load_spice_rhs_tran)(void *inst, void *model, double *dst, double *prev_solve, double alpha);
    void (*load_jacobian_resist)(void *inst, void *model);
    void (*load_jacobian_react)(void *inst, void *model, double alpha);
    void (*load_jacobian_tran)(void *inst, void *model, double alpha);
} wrsim_osdi_descriptor;

#endif
