/** Host support for a user's rules: reading a user's knowledge-base file
clause by clause, and running a query typed at the REPL.

fm_consult(+Path, +Settings, -Result) reads every term of Path, checks
it, and only if the whole file is sound replaces the settings it defines
(predicates of Settings, e.g. [strategy/1, bound/2]: strategy/1 whole,
bound/2 by name) and adds the other clauses. Result is ok(Count) or error(Line, Reason).
*/

:- use_module(library(lists)).
:- use_module(library(iso_ext)).
:- use_module(library(charsio)).

fm_consult(Path, Settings, Result) :-
    catch(fm_read_all_(Path, Items), E, true),
    (   nonvar(E) -> fm_error_line_(E, Line), fm_reason_(E, Why), Result = error(Line, Why)
    ;   fm_check_all_(Items, Problem) -> Result = Problem
    ;   fm_saved_settings_(Items, Settings, Saved),
        catch(fm_add_all_(Items, Settings, N), E2, true),
        (   nonvar(E2) ->
            fm_undo_(Items, Saved), fm_reason_(E2, Why2), Result = error(0, Why2)
        ;   fm_probe_all_(Items, Problem2) ->
            fm_undo_(Items, Saved), Result = Problem2
        ;   Result = ok(N)
        )
    ).

fm_read_all_(Path, Items) :-
    setup_call_cleanup(open(Path, read, S), fm_read_items_(S, Items), close(S)).

% Each item carries the line its clause ends on (the reader stops after
% the clause's closing full stop and the layout character after it).
fm_read_items_(S, Items) :-
    read_term(S, T, []),
    (   T == end_of_file -> Items = []
    ;   stream_property(S, position(position_and_lines_read(_, Line))),
        Items = [item(Line, T) | Rest],
        fm_read_items_(S, Rest)
    ).

fm_error_line_(error(_, _:L), L) :- integer(L), !.
fm_error_line_(_, 0).

fm_reason_(error(syntax_error(W), _), R) :- !, R = syntax_error(W).
fm_reason_(error(E, _), E) :- !.
fm_reason_(E, E).

% fm_check_all_(+Items, -Problem): Problem is the first unsound item.
fm_check_all_([item(L, T) | Items], Problem) :-
    (   fm_check_(T, Why) -> Problem = error(L, Why)
    ;   fm_check_all_(Items, Problem)
    ).

fm_check_((:- D), Why) :- !,
    (   fm_directive_ok_(D) -> fail ; Why = unsupported_directive(D) ).
fm_check_((H :- _), Why) :- !, fm_check_head_(H, Why).
fm_check_(H, Why) :- fm_check_head_(H, Why).

fm_check_head_(H, Why) :-
    (   var(H) -> Why = head_is_a_variable
    ;   \+ callable(H) -> Why = head_not_callable(H)
    ;   functor(H, N, A), fm_protected_(N, A) -> Why = cannot_redefine(N/A)
    ;   fm_action_arg_(H, Act), nonvar(Act), \+ fm_known_action_(Act) ->
        functor(Act, AN, AA), Why = undefined_action(AN/AA)
    ).

fm_protected_(N, A) :-
    functor(H, N, A),
    predicate_property(H, built_in).
fm_protected_(N, A) :-
    functor(H, N, A),
    predicate_property(H, defined),
    \+ predicate_property(H, dynamic).

fm_action_arg_(feature_action(_, _, A), A).
fm_action_arg_(redesign_rule(_, _, _, _, A), A).

fm_directive_ok_(dynamic(_)).
fm_directive_ok_(discontiguous(_)).
fm_directive_ok_(use_module(library(_))).

fm_add_all_(Items, Settings, N) :-
    fm_settings_defined_(Items, Settings, Gs),
    forall(member(G, Gs), retractall(G)),
    fm_add_items_(Items, 0, N).

% The settings (of Settings) the file defines, as the general heads of the
% clauses it replaces: a setting of arity 1 (strategy/1) is replaced
% whole, one of arity 2 or more (bound/2) name by name, by its first
% argument, so that a file holding bound(upper_corner, 140) leaves the
% other bounds as they were.
fm_settings_defined_(Items, Settings, Gs) :-
    findall(Key,
            ( member(item(_, T), Items), fm_head_(T, H),
              functor(H, N0, A0), member(N0/A0, Settings),
              fm_setting_key_(H, Key) ),
            Keys0),
    sort(Keys0, Keys),
    findall(G,
            ( member(Key, Keys),
              \+ ( Key = name(N, A, _), member(whole(N, A), Keys) ),
              fm_key_head_(Key, G) ),
            Gs).

fm_setting_key_(H, name(N, A, Name)) :-
    functor(H, N, A),
    A >= 2,
    arg(1, H, Name),
    atomic(Name),
    !.
fm_setting_key_(H, whole(N, A)) :-
    functor(H, N, A).

fm_key_head_(whole(N, A), G) :- functor(G, N, A).
fm_key_head_(name(N, A, Name), G) :- functor(G, N, A), arg(1, G, Name).

% The clauses of the settings the file replaces, to restore on undo.
fm_saved_settings_(Items, Settings, Saved) :-
    fm_settings_defined_(Items, Settings, Gs),
    findall((G :- B), (member(G, Gs), clause(G, B)), Saved).

% Takes a refused file back out: its clauses retracted, the settings it
% replaced restored.
fm_undo_(Items, Saved) :-
    forall(member(item(_, T), Items),
           (   T = (:- _) -> true
           ;   fm_clause_(T, C), catch(retract(C), _, true) -> true
           ;   true
           )),
    forall(member(C, Saved), assertz(C)).

fm_clause_((H :- B), (H :- B)) :- !.
fm_clause_(H, (H :- true)).

/* Run-time check of a file: the body of each rule of a predicate the
   host asks is called on sample contexts; a rule that throws or runs
   away on them is refused with its line. */

fm_probe_all_(Items, error(L, Why)) :-
    member(item(L, (H :- B)), Items),
    fm_probe_(P),
    copy_term(H-B, H1-B1),
    H1 = P,
    fm_probe_body_(B1, H, Why),
    !.

fm_probe_body_(B, H, Why) :-
    functor(H, Name, Arity),
    catch(once(call_with_inference_limit(B, 1000000, R)), E, true),
    (   nonvar(E) -> fm_formal_(E, F), Why = rule_raised(Name/Arity, F)
    ;   R == inference_limit_exceeded -> Why = rule_runs_away(Name/Arity)
    ).

fm_probe_(feature(_, C)) :- fm_probe_ctx_(C).
fm_probe_(feature_action(_, C, _)) :- fm_probe_ctx_(C).
fm_probe_(violation(R, _)) :- fm_probe_relation_(R).
fm_probe_(redesign_rule(_, C, A, V, _)) :-
    fm_probe_ctx_(C), fm_probe_action_(A), fm_probe_violation_(V).
fm_probe_(final_pattern(As, _, _)) :-
    member(As, [[90, 90, 180, 90, 90, 180], [120, 120, 120, 120, 120, 120],
                [60, 200, 90, 100, 150, 120]]).
fm_probe_(closing_way(N, _)) :- member(N, [4, 6, 8, 12]).
fm_probe_(strategy(_)).
fm_probe_(bound(_, _)).

fm_probe_ctx_(ctx(90, 180, 90, 180, 90, 1, 1, 1)).
fm_probe_ctx_(ctx(180, 180, 180, 180, 180, 1, 1, 1)).
fm_probe_ctx_(ctx(100, 200, 60, 250, 120, 0.5, 2.0, 1)).
fm_probe_ctx_(ctx(270, 90, 300, 45, 170, 1.5, 0.7, 1)).
% a graded run's context: a flat front where the size aimed for is 2.5
% times the edge
fm_probe_ctx_(ctx(180, 180, 180, 180, 180, 1, 1, 2.5)).

fm_probe_action_(a1(90, 90, 1, 1)).
fm_probe_action_(a2(90, 90)).
fm_probe_action_(a3).
fm_probe_action_(a4).

fm_probe_violation_(V) :-
    member(V, [near_boundary(n3), near_concave(e23), near_node(n4),
               small_outer_corner(n1), small_corner(n3), large_corner(n4),
               small_remaining(n3)]).

fm_probe_relation_(R) :-
    member(R, [corner_segment(n3, 0.1, 0.0, 1.0), corner_node(n3, 0.2, 1.0),
               edge_point(e23, 0.1, 0.0, 1.0, 270), outer_corner(n1, 30),
               inner_corner(n3, 150), remaining_corner(n3, 30)]).

fm_head_((H :- _), H) :- !.
fm_head_((:- _), _) :- !, fail.
fm_head_(H, H).

fm_add_items_([], N, N).
fm_add_items_([item(_, T) | Items], N0, N) :-
    (   T = (:- D) -> call(D), N1 = N0
    ;   assertz(T), N1 is N0 + 1
    ),
    fm_add_items_(Items, N1, N).

/* Host support: a user's query, typed at the REPL. */

%% fm_repl_query(+Codes, +Limit, -Answer)
%
% Reads the query from its character codes (so no text the user types
% can break the host's query), calls it with at most Limit inferences per
% answer and gives, one per solution on backtracking:
%   answer(Bindings, More)
%                      Bindings a list of Name = Text (the value written
%                      as Prolog text, variables by their names); More is
%                      last when no other answer can follow, else more
%   error(Text)        a syntax error, an exception or a runaway; last
fm_repl_query(Codes, Limit, Answer) :-
    atom_codes(Atom, Codes),
    atom_chars(Atom, Chars),
    catch(read_term_from_chars(Chars, Goal, [variable_names(Vs)]), E, true),
    (   nonvar(E) -> fm_error_text_(E, Answer)
    ;   catch(call_with_inference_limit(Goal, Limit, R), E2, true),
        (   nonvar(E2) -> fm_error_text_(E2, Answer)
        ;   R == inference_limit_exceeded ->
            Answer = error('the query ran past the inference limit (a loop?)')
        ;   fm_fresh_names_(Vs, Names),
            fm_bindings_(Vs, Names, Bs),
            % R is ! when the goal left no choice point: no answer can follow
            (   R == ! -> More = last ; More = more ),
            Answer = answer(Bs, More)
        )
    ).

% The variables of the answers the query did not name are written _A,
% _B, ... (as the engine's own toplevel does), never as a name of the
% query's.
fm_fresh_names_(Vs, Names) :-
    term_variables(Vs, Free),
    fm_name_free_(Free, Vs, 0, Extra),
    append(Vs, Extra, Names).

fm_name_free_([], _, _, []).
fm_name_free_([V | Free], Vs, I, Extra) :-
    (   member(_ = W, Vs), W == V -> Extra = Extra1, I1 = I
    ;   fm_fresh_name_(I, Vs, Name, I1), Extra = [Name = V | Extra1]
    ),
    fm_name_free_(Free, Vs, I1, Extra1).

fm_fresh_name_(I, Vs, Name, I1) :-
    Letter is 0'A + I mod 26,
    (   I < 26 -> atom_codes(Name0, [0'_, Letter])
    ;   N is I // 26, number_codes(N, Ds), atom_codes(Name0, [0'_, Letter | Ds])
    ),
    I0 is I + 1,
    (   member(Name0 = _, Vs) -> fm_fresh_name_(I0, Vs, Name, I1)
    ;   Name = Name0, I1 = I0
    ).

fm_bindings_([], _, []).
fm_bindings_([Name = V | Rest], Vs, Bs) :-
    write_term_to_chars(V, [quoted(true), variable_names(Vs)], Cs),
    atom_chars(Text, Cs),
    (   ( sub_atom(Name, 0, 1, _, '_') ; Text == Name ) -> Bs = Bs1
    ;   Bs = [Name = Text | Bs1]
    ),
    fm_bindings_(Rest, Vs, Bs1).

fm_error_text_(E, error(Text)) :-
    fm_error_words_(E, W),
    write_term_to_chars(W, [quoted(true)], Cs),
    atom_chars(Text, Cs).

fm_error_words_(error(syntax_error(S), _), syntax_error(S)) :- !.
fm_error_words_(error(existence_error(procedure, PI), _), unknown_procedure(PI)) :- !.
fm_error_words_(error(E, _), E) :- !.
fm_error_words_(E, exception(E)).
