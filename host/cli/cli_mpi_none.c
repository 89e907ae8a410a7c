/* SPDX-License-Identifier: MIT */
/* limn built without MPI (LIMN_MPI off): always one rank (cli.h, "MPI"). */
#include "cli.h"

int cli_mpi_launched(void) { return 0; }
int cli_mpi_main(int argc, char **argv, int (*dispatch)(int, char **))
{
    return dispatch(argc, argv);
}
int cli_mpi_ranks(void) { return 1; }
int cli_mpi_rank(void) { return 0; }
limn_status cli_mpi_agree(limn_context *ctx, limn_status st)
{
    (void)ctx;
    return st;
}
int cli_mpi_root_rc(int rc) { return rc; }
void cli_mpi_set_per_rank(int on) { (void)on; }
int cli_mpi_per_rank(void) { return 0; }
void cli_mpi_note_memory(void) {}
void cli_mpi_json(json_out *j) { (void)j; }
void cli_mpi_print(void) {}

/* never called with one rank; here so that the commands link */
static limn_status none(void) { return LIMN_ERR_ARGUMENT; }
limn_status cli_mpi_interpolate(limn_context *ctx, const limn_mesh *mesh,
                                const limn_interpolate_options *o, limn_mesh **control,
                                limn_report *r, limn_mesh **piece)
{
    (void)ctx, (void)mesh, (void)o, (void)control, (void)r, (void)piece;
    return none();
}
limn_status cli_mpi_smooth(limn_context *ctx, const limn_mesh *mesh,
                           const limn_series_options *o, int terms, limn_mesh **out,
                           limn_series_report *r, limn_mesh **piece)
{
    (void)ctx, (void)mesh, (void)o, (void)terms, (void)out, (void)r, (void)piece;
    return none();
}
limn_status cli_mpi_denoise(limn_context *ctx, const limn_mesh *mesh,
                            const limn_series_options *o, int m, int steps, int keep_volume,
                            limn_mesh **out, limn_series_report *r, limn_mesh **piece)
{
    (void)ctx, (void)mesh, (void)o, (void)m, (void)steps, (void)keep_volume, (void)out, (void)r,
        (void)piece;
    return none();
}
limn_status cli_mpi_denoise_sure(limn_context *ctx, const limn_mesh *mesh,
                                 const limn_series_options *o, int products, int *keep_volume,
                                 limn_mesh **out, double *sigma, limn_series_report *r,
                                 limn_mesh **piece)
{
    (void)ctx, (void)mesh, (void)o, (void)products, (void)keep_volume, (void)out, (void)sigma,
        (void)r, (void)piece;
    return none();
}
limn_status cli_mpi_sharpen(limn_context *ctx, const limn_mesh *mesh,
                            const limn_series_options *o, int from, int to, int steps,
                            limn_mesh **out, limn_series_report *r, limn_mesh **piece)
{
    (void)ctx, (void)mesh, (void)o, (void)from, (void)to, (void)steps, (void)out, (void)r,
        (void)piece;
    return none();
}
limn_status cli_mpi_bands(limn_context *ctx, const limn_mesh *mesh, const limn_series_options *o,
                          int count, double *bands, double *energy, limn_series_report *r)
{
    (void)ctx, (void)mesh, (void)o, (void)count, (void)bands, (void)energy, (void)r;
    return none();
}
limn_status cli_mpi_morph(limn_context *ctx, const limn_mesh *from, const limn_mesh *to,
                          const limn_morph_options *o, limn_morph_frame_fn fn, void *user,
                          limn_series_report *r)
{
    (void)ctx, (void)from, (void)to, (void)o, (void)fn, (void)user, (void)r;
    return none();
}
int cli_mpi_sliced(const char *input, limn_format in_format, const char *output, int per_rank)
{
    (void)input, (void)in_format, (void)output, (void)per_rank;
    return 0;
}
limn_status cli_mpi_interpolate_sliced(limn_context *ctx, const cli_sliced_job *job,
                                       const limn_interpolate_options *o, limn_report *r,
                                       limn_write_report *written, double seconds[2])
{
    (void)ctx, (void)job, (void)o, (void)r, (void)written, (void)seconds;
    return none();
}
limn_status cli_mpi_series_sliced(limn_context *ctx, const cli_sliced_job *job,
                                  const limn_series_options *o, const cli_series_call *call,
                                  limn_series_report *r, limn_write_report *written,
                                  double *displacement, double seconds[2])
{
    (void)ctx, (void)job, (void)o, (void)call, (void)r, (void)written, (void)displacement,
        (void)seconds;
    return none();
}
limn_status cli_mpi_bands_sliced(limn_context *ctx, const cli_sliced_job *job,
                                 const limn_series_options *o, int count, cli_bands_out *out,
                                 limn_series_report *r, double seconds[2])
{
    (void)ctx, (void)job, (void)o, (void)count, (void)out, (void)r, (void)seconds;
    return none();
}
limn_status cli_mpi_morph_sliced(limn_context *ctx, const cli_sliced_job *job,
                                 const char *to_path, const limn_morph_options *o,
                                 cli_morph_sink *sink, limn_series_report *r, double seconds[2])
{
    (void)ctx, (void)job, (void)to_path, (void)o, (void)sink, (void)r, (void)seconds;
    return none();
}
char *cli_mpi_rank_path(const char *path)
{
    (void)path;
    return NULL;
}
limn_status cli_mpi_subdivide_sliced(limn_context *ctx, const cli_sliced_job *job,
                                     const limn_subdivide_options *o, limn_subdivide_report *r,
                                     limn_write_report *written, double seconds[2])
{
    (void)ctx, (void)job, (void)o, (void)r, (void)written, (void)seconds;
    return none();
}
