/** Host support: the mesher's questions and the live front, loaded with
the built-in rules. What a user's file or query needs (reading a file
clause by clause, the REPL's queries) is in user_loader.pl, loaded the
first time a user's rules come in: its libraries cost a run a sixth of
the engine's start. */

:- use_module(library(lists)).

% The actions the host knows how to carry out (a user's rule may only
% answer with these).
fm_known_action_(a1(_, _, _, _)).
fm_known_action_(a2(_, _)).
fm_known_action_(a3).
fm_known_action_(a4).
fm_known_action_(t3(_)).
fm_known_action_(shift(_, A)) :- (var(A) -> true ; fm_known_action_(A)).
fm_known_action_(merge(_, _)).

fm_formal_(error(F, _), F) :- !.
fm_formal_(E, E).

/* Host support: the live front as facts (kb/front.pl). */

%% fm_front_set(+Nodes, +Edges, +Angles, +Contexts)
%
% Replaces the front facts: Nodes are xy(N, X, Y), Edges e(N1, N2),
% Angles a(N, Degrees), Contexts c(E, N, Ctx) (the front edge E read
% from its end N).
fm_front_set(Nodes, Edges, Angles, Ctxs) :-
    retractall(node_xy(_, _, _)),
    retractall(front_edge(_, _)),
    retractall(node_angle(_, _)),
    retractall(edge_context(_, _, _)),
    fm_assert_as_(Nodes, node_xy),
    fm_assert_as_(Edges, front_edge),
    fm_assert_as_(Angles, node_angle),
    fm_assert_as_(Ctxs, edge_context).

% fm_assert_as_(+Terms, +Name): each term's arguments asserted as a fact
% Name(Args...) (forall/2 is library(iso_ext)'s, which only a user's
% rules bring in).
fm_assert_as_([], _).
fm_assert_as_([T | Ts], Name) :-
    T =.. [_ | Args],
    F =.. [Name | Args],
    assertz(F),
    fm_assert_as_(Ts, Name).

/* Host support: the mesher's questions, each bounded, so that a user's
   rule that throws or runs away on some edge stops the run with the
   rule's name instead of hanging it or crashing it. */

%% fm_design(+Ctx, -R)
%
% R = d(Feature, Action) for the first feature of the strategy the edge
% shows, or fault(Rule, Why) when a rule threw (raised(E)) or ran past
% the inference limit (runs_away). Fails when the edge shows no feature.
fm_design(Ctx, R) :-
    fm_bounded_(context_design(Ctx, F, A), Outcome),
    (   Outcome == true -> R = d(F, A)
    ;   Outcome = fault(Why), fm_design_culprit_(Ctx, Rule), R = fault(Rule, Why)
    ).

%% fm_design_packed(+Angles, +H5, +H6, +HR, -R)
%
% fm_design/2 with the context packed by the host: the five angles
% Theta7, Theta4, Theta1, Theta2, Theta5 as base-1000 digits of Angles,
% L5, L6 and the grading ratio in hundredths (the query text is then
% short to read).
fm_design_packed(P, H5, H6, HR, R) :-
    T5 is P mod 1000, P1 is P // 1000,
    T2 is P1 mod 1000, P2 is P1 // 1000,
    T1 is P2 mod 1000, P3 is P2 // 1000,
    T4 is P3 mod 1000, T7 is P3 // 1000,
    L5 is H5 / 100.0, L6 is H6 / 100.0, G is HR / 100.0,
    fm_design(ctx(T7, T4, T1, T2, T5, L5, L6, G), R).

%% fm_designs(+Items, -Rs)
%
% fm_design/2 over a batch of edges, in one query: Items are p(Angles,
% H5, H6, HR) (packed as for fm_design_packed/5) or c(Ctx); Rs holds each
% one's R in order, or none where the edge shows no feature.
fm_designs([], []).
fm_designs([I | Is], [R | Rs]) :-
    (   fm_design_item_(I, R0) -> R = R0 ; R = none ),
    fm_designs(Is, Rs).

fm_design_item_(p(P, H5, H6, HR), R) :- fm_design_packed(P, H5, H6, HR, R).
fm_design_item_(c(Ctx), R) :- fm_design(Ctx, R).

%% fm_redesign(+Ctx, +Action, +Relations, -R)
%
% R = r(Rule, NewAction), or fault(Rule, Why). Fails when no rule fires.
fm_redesign(Ctx, A, Rels, R) :-
    fm_bounded_(redesign(Ctx, A, Rels, Rule, NewA), Outcome),
    (   Outcome == true -> R = r(Rule, NewA)
    ;   Outcome = fault(Why), fm_redesign_culprit_(Ctx, A, Rels, Culprit),
        R = fault(Culprit, Why)
    ).

%% fm_patterns(+Angles, -R)
%
% R = ps(Patterns), or fault(final_pattern, Why).
fm_patterns(As, R) :-
    fm_bounded_(loop_patterns(As, Ps), Outcome),
    (   Outcome == true -> R = ps(Ps)
    ;   Outcome = fault(Why), R = fault(final_pattern, Why)
    ).

%% fm_closing_ways(+Segments, -R)
%
% R = ws(Ways), the ways closing_way/2 allows for a loop of Segments,
% or fault(closing_way, Why).
fm_closing_ways(N, R) :-
    fm_bounded_(findall(W, closing_way(N, W), Ws), Outcome),
    (   Outcome == true -> R = ws(Ws)
    ;   Outcome = fault(Why), R = fault(closing_way, Why)
    ).

% Only the built-in rules are loaded (the host states it, and takes it
% back before it consults a user's file or runs a user's query): they end
% on every question (no recursion but over short lists), so the inference
% bound, which costs a fifth of a question's time, is kept for the rules
% users add.
:- dynamic(fm_only_built_in_rules_/0).

fm_bounded_(G, Outcome) :-
    (   fm_only_built_in_rules_ -> catch(G, E, true), L = true
    ;   catch(call_with_inference_limit(G, 2000000, L), E, true)
    ),
    (   nonvar(E) -> fm_formal_(E, F), Outcome = fault(raised(F))
    ;   L == inference_limit_exceeded -> Outcome = fault(runs_away)
    ;   Outcome = true
    ).

fm_faulty_(G) :- fm_bounded_(G, O), O = fault(_).

% The rule at fault in a design question: the first feature of the
% strategy whose recognition or action throws or runs away.
fm_design_culprit_(Ctx, Rule) :-
    strategy(S),
    member(F, S),
    (   fm_faulty_(feature(F, Ctx)) -> Rule = feature(F)
    ;   fm_faulty_((feature(F, Ctx), feature_action(F, Ctx, _))) -> Rule = feature_action(F)
    ),
    !.
fm_design_culprit_(_, context_design).

fm_redesign_culprit_(Ctx, A, Rels, Rule) :-
    member(Rel, Rels),
    (   fm_faulty_(violation(Rel, _)) -> Rule = violation(Rel)
    ;   fm_faulty_((violation(Rel, V), redesign_rule(_, Ctx, A, V, _))) ->
        Rule = redesign_rule
    ),
    !.
fm_redesign_culprit_(_, _, _, redesign).

/* Host support: a variant's bounds in place for a run of its own on
this engine, and every bound as it was after it (the coarser pass). */

:- dynamic(fm_saved_bounds_/1).

%% fm_bounds_push(+Pairs)
%
% Saves the bound/2 clauses, then sets bound(N, V) for each N-V of Pairs
% in place of the bound of that name.
fm_bounds_push(Pairs) :-
    findall((bound(N, V) :- B), clause(bound(N, V), B), Saved),
    asserta(fm_saved_bounds_(Saved)),
    fm_bounds_set_(Pairs).

fm_bounds_set_([]).
fm_bounds_set_([N-V | Pairs]) :-
    retractall(bound(N, _)),
    assertz(bound(N, V)),
    fm_bounds_set_(Pairs).

%% fm_bounds_pop
%
% The bound/2 clauses as the last fm_bounds_push found them, in order.
fm_bounds_pop :-
    retract(fm_saved_bounds_(Saved)),
    !,
    retractall(bound(_, _)),
    fm_assert_all_(Saved).

fm_assert_all_([]).
fm_assert_all_([C | Cs]) :-
    assertz(C),
    fm_assert_all_(Cs).
