//! A restored path stage (FMU state) is checked before it is used: every point of its geometry
//! within the coordinate range, arcs no longer than the turns a program may ask for, chains,
//! parts and transitions consistent, speeds and limits positive.

use super::tolerance::{BOUND_ROUNDING, LENGTH_ROUNDING};
use super::{Blend, Chain, Curve, Hermite, Move, PathBlock, PathBuilder, Piece, Segment, Whole};
use crate::config::Machine;
use crate::gcode::check::{MAX_COORDINATE_M, MAX_DWELL_S, MAX_TURNS};
use crate::geometry::{Arc, Line, Source};
use crate::valid::{point, unit_vector, within, MAX_POSITION_M, MAX_SPEED_M_S};
use std::f64::consts::TAU;

type Check = Result<(), String>;

fn line(l: &Line) -> Check {
    point("line start", l.start, MAX_POSITION_M)?;
    point("line end", l.end, MAX_POSITION_M)
}

fn arc(a: &Arc) -> Check {
    for p in [a.center, a.start, a.end] {
        point("arc point", p, MAX_POSITION_M)?;
    }
    within("arc radius", a.radius, f64::MIN_POSITIVE, MAX_POSITION_M)?;
    within("arc sweep", a.sweep, f64::MIN_POSITIVE, TAU * (MAX_TURNS + 1.0))?;
    within("helix rise", a.rise, -MAX_POSITION_M, MAX_POSITION_M)?;
    for v in [a.e1, a.e2, a.axis] {
        unit_vector("arc axis", v)?;
    }
    Ok(())
}

fn blend(b: &Blend) -> Check {
    point("transition corner", b.corner, MAX_POSITION_M)?;
    unit_vector("transition direction", b.u)?;
    unit_vector("transition direction", b.v)?;
    within("transition half", b.half, 0.0, MAX_POSITION_M)?;
    within("transition length", b.length, 0.0, MAX_POSITION_M)
}

fn hermite(h: &Hermite) -> Check {
    point("curve start", h.start, MAX_POSITION_M)?;
    point("curve end", h.end, MAX_POSITION_M)?;
    within("curve length", h.lambda, f64::MIN_POSITIVE, MAX_POSITION_M)?;
    h.check_state()
}

fn curve(c: &Curve) -> Check {
    match c {
        Curve::Line(l) => line(l),
        Curve::Arc(a) => arc(a),
        Curve::Hermite(h) => hermite(h),
    }
}

fn piece(p: &Piece) -> Check {
    curve(&p.curve)?;
    let length = p.curve.length();
    within("piece start", p.u0, 0.0, length)?;
    within("piece end", p.u1, p.u0, length * (1.0 + BOUND_ROUNDING))
}

fn chain(c: &Chain) -> Check {
    c.check_state()?;
    c.pieces.iter().try_for_each(piece)
}

/// A programmed move held by the smooth builder.
pub(super) fn programmed(m: &Move) -> Check {
    match &m.source {
        Source::Line(l) => line(l)?,
        Source::Arc(a) => arc(a)?,
    }
    within("move feed", m.feed, 0.0, MAX_SPEED_M_S)?;
    within("move tolerance", m.tolerance, 0.0, MAX_COORDINATE_M)?;
    within("tiny moves taken", m.absorbed, 0.0, MAX_COORDINATE_M)
}

/// A held piece of the smooth builder, or a chain being filled (possibly empty).
pub(super) fn pieces(c: &Chain) -> Check {
    if c.is_empty() {
        return Ok(());
    }
    chain(c)
}

pub(super) fn one_piece(p: &Piece) -> Check {
    piece(p)
}

fn whole(w: &Whole) -> Check {
    match w {
        Whole::Line(l) => line(l),
        Whole::Arc(a) => arc(a),
        Whole::Blend(b) => blend(b),
        Whole::Chain(c) => chain(c),
    }
}

impl Segment {
    pub fn check_state(&self) -> Check {
        match self {
            Segment::Chain(c) => chain(c),
            Segment::Line(l) => line(l),
            Segment::Arc(a) => arc(a),
            Segment::Blend(b) => blend(b),
            Segment::Dwell { at, seconds } => {
                point("dwell point", *at, MAX_POSITION_M)?;
                within("dwell", *seconds, 0.0, MAX_DWELL_S)
            }
            Segment::Part {
                whole: w, s0, len, ..
            } => {
                whole(w)?;
                let total = w.length();
                within("part start", *s0, 0.0, total)?;
                within(
                    "part length",
                    *len,
                    0.0,
                    (total - s0) * (1.0 + BOUND_ROUNDING) + LENGTH_ROUNDING,
                )
            }
        }
    }
}

impl PathBlock {
    /// A restored segment ready for planning.
    pub fn check_state(&self) -> Check {
        self.segment.check_state()?;
        within("segment feed", self.v_feed, 0.0, MAX_SPEED_M_S)?;
        within("junction speed", self.v_end_max, 0.0, MAX_SPEED_M_S)?;
        let l = &self.limits;
        within("speed limit", l.v_max, 0.0, MAX_SPEED_M_S)?;
        for x in [l.a_max, l.j_max, l.snap_max] {
            within("path limit", x, 0.0, f64::INFINITY)?;
        }
        self.bands.check_state()
    }
}

impl PathBuilder {
    /// A restored builder: for this machine, its held segment and builders checked.
    pub fn check_state(&self, machine: &Machine) -> Check {
        let fresh = PathBuilder::new(machine);
        if self.machine != *machine || self.transition_machine != fresh.transition_machine {
            return Err("path stage: saved for another machine".into());
        }
        if let Some(h) = &self.held {
            h.block.check_state()?;
            within(
                "held length",
                h.programmed,
                0.0,
                MAX_POSITION_M * TAU * (MAX_TURNS + 1.0),
            )?;
        }
        self.smooth.check_state()?;
        self.merger.check_state()?;
        self.micro.check_state()
    }
}
