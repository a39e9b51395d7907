/* bvh_packet.h: rays walked together, and what a packet must share for the
** box test (bvh.h) never to reject a box one of them would enter. */
#ifndef LC_BVH_PACKET_H
#define LC_BVH_PACKET_H

#include "bvh.h"

/* Rays walked together by the queries over arrays (intersect.c): at most
** this many, neighbours in the caller's array. */
#define BVH_PACKET 8

/* A packet as the box test reads it: its rays' one origin and the lower
** bounds of their reciprocal directions per axis in lo (lo.o, lo.inv),
** the upper bounds in ihi; their signs all its rays share (lo.neg), all
** finite. Rays from different origins do not make packets: a terrain's
** shadow rays, eight neighbours from eight points, passed a box test over
** the bounds of their origins at 94 leaves a ray where each met two, and
** took 2.6 times as long as walking one by one. */
typedef struct {
    bvh_ray lo;
    double  ihi[3];
} bvh_packet;

/* Adds ray q to packet *p: 0 when q cannot join, its origin another or
** its reciprocals differing in sign on an axis from the packet's, or one
** infinite (a direction along an axis plane, whose slab distances may be
** NaN). */
static inline int bvh_packet_add(bvh_packet *p, const bvh_ray *q)
{
    for (int k = 0; k < 3; k++) {
        double inv = q->inv[k];
        if (q->o[k] != p->lo.o[k] || q->neg[k] != p->lo.neg[k] || !(fabs(inv) <= DBL_MAX))
            return 0;
        p->lo.inv[k] = inv < p->lo.inv[k] ? inv : p->lo.inv[k];
        p->ihi[k] = inv > p->ihi[k] ? inv : p->ihi[k];
    }
    return 1;
}

/* Starts *p with ray q, which must pass bvh_packet_add's checks as the
** others do (0 if not). */
static inline int bvh_packet_start(bvh_packet *p, const bvh_ray *q)
{
    p->lo = *q;
    for (int k = 0; k < 3; k++)
        p->ihi[k] = q->inv[k];
    return bvh_packet_add(p, q);
}

#endif
